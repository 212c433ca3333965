// tricot dic's pipeline (THEORY §10, DESIGN.md "dic"): the config with the command line over it, the
// sequence run image by image (a long sequence never sits in memory) and its tables: DIR/points.csv,
// DIR/frames.csv, one overlay per frame, and on request DIR/increments.csv and DIR/specimen.csv.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tricot/dic/physical.hpp"
#include "tricot/dic/sequence.hpp"
#include "tricot/project/dic_spec.hpp"
#include "tricot/project/log.hpp"

namespace tricot::project {

/// The command line's settings; each one given replaces its key of [dic].
struct DicFlags {
  std::optional<int> subset;  ///< --subset → dic.subset_size (checked by dic::IcgnOptions::validate)
  std::optional<int> step;    ///< --step → dic.step
  std::string mode;  ///< --mode → dic.mode
  std::string roi;   ///< --roi X0,Y0,X1,Y1 → dic.roi (and no roi_polygon, roi_mask)
};

/// Reads `file` ("" = every key at its default) and sets the keys the flags give. Throws
/// InputError/FileError for the file; the flags' values are checked by DicSpec::settings().
DicSpec dic_spec(const std::string& file, const DicFlags& flags);

struct DicRun {
  dic::SequenceResult result;
  DicSettings settings;
  std::vector<std::string> warnings;  ///< one per image converted to gray
  std::string written;                ///< what was written, for the summary line
};
/// Runs the sequence `images` (the first is the reference) and writes its tables to `out`. Every image
/// must exist before any work starts (FileError); an image of another size than the reference is a
/// FileError; a reference without texture in the region of interest an InputError.
DicRun run_dic(const DicSpec& spec, const std::vector<std::string>& images, const std::filesystem::path& out,
               const Log& log);

/// DIR/points.csv: frame,id,x0,y0,x,y,u,v,zncc,status,exx,eyy,exy (empty cells where there is no value).
std::string points_csv(const dic::SequenceResult& r);
/// DIR/frames.csv: frame,image,reference_frame,ok,points,mean_zncc,seconds.
std::string frames_csv(const dic::SequenceResult& r, const std::vector<std::string>& images);
/// DIR/increments.csv: from,to,id,x,y,u,v,zncc,status (fixed-point incremental fields).
std::string increments_csv(const dic::SequenceResult& r);
/// DIR/specimen.csv: points.csv in specimen millimetres.
std::string specimen_csv(const dic::SequenceResult& r, const dic::PhysicalFrame& p);

}  // namespace tricot::project
