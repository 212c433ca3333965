// tricot dic's pipeline (docs/theory.md §10, docs/design.md): the config with the command line over it, the
// sequence run image by image (a long sequence never sits in memory) and its tables: DIR/points.csv,
// DIR/frames.csv, one overlay per frame, and on request DIR/increments.csv and DIR/specimen.csv.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tricot/dic/physical.hpp"
#include "tricot/dic/sequence.hpp"
#include "tricot/io/vtu.hpp"
#include "tricot/project/dic_spec.hpp"
#include "tricot/project/log.hpp"

namespace tricot::project {

/// The command line's settings; each one given replaces its key of [dic].
struct DicFlags {
  std::optional<int> subset;  ///< --subset → dic.subset_size (checked by dic::IcgnOptions::validate)
  std::optional<int> step;    ///< --step → dic.step
  std::string mode;           ///< --mode → dic.mode
  std::string roi;            ///< --roi X0,Y0,X1,Y1 → dic.roi (and no roi_polygon, roi_mask)
};

/// Reads `file` ("" = every key at its default) and sets the keys the flags give. Throws
/// InputError/FileError for the file; the flags' values are checked by DicSpec::settings().
DicSpec dic_spec(const std::string& file, const DicFlags& flags);

/// How run_dic runs, besides the spec (the command line's --resume; what a caller keeps in memory).
struct DicRunOptions {
  /// Continue a killed run into the same folder with the same spec and images from its last complete
  /// frame (the checkpoint kept in DIR/.tricot-dic/). Without a checkpoint there, the run starts from
  /// frame 0. The files written equal those of an uninterrupted run (frames.csv's seconds aside).
  bool resume = false;
  /// Keep every frame in DicRun::result.frames. false: only the last frame is kept and memory stays
  /// bounded whatever the number of frames (the files are written frame by frame either way).
  bool keep_frames = true;
};

/// Wall seconds per stage, summed over the frames a run correlated (issue 16: where the time goes).
struct DicStageSeconds {
  double check = 0;       ///< decoding every frame once before any work, to check its size
  double decode = 0;      ///< decoding each frame for its correlation
  double prepare = 0;     ///< B-spline coefficients and gradients (dic::TrackedFrame::Stages)
  double correlate = 0;   ///< seeds, propagation and IC-GN
  double strain = 0;      ///< the strain fit
  double increments = 0;  ///< fixed-point incremental fields
  double tables = 0;      ///< formatting and appending the CSV rows
  double overlays = 0;    ///< drawing and encoding the overlays
  double fields = 0;      ///< the VTU files
  double checkpoint = 0;  ///< the --resume checkpoint of each frame
  /// "check 1.2 s, decode 0.3 s, ..." (the stages that took any time).
  std::string brief_report() const;
};

struct DicRun {
  /// The frames (all of them with DicRunOptions::keep_frames, else the last; after a resume, those
  /// from the checkpoint's frame on), termination and message.
  dic::SequenceResult result;
  DicSettings settings;
  std::vector<std::string> warnings;  ///< one per image converted to gray
  std::string written;                ///< what was written, for the summary line
  int frames = 0;                     ///< frames in points.csv, frame 0 included
  int lost_at = -1;                   ///< the first frame with no point ok (−1: none)
  int resumed_from = 0;               ///< the first frame correlated by this run (> 1 after a resume)
  DicStageSeconds stages;
};
/// Runs the sequence `images` (the first is the reference) and writes its tables to `out`, frame by
/// frame: points.csv and the other tables grow in the staging folder as each frame is correlated, and
/// are published together at the end (OutputDir), so a killed run leaves no torn published file but
/// a checkpoint that `options.resume` continues from. Only the reference and the current (and
/// previous) images are held. Every image must exist and be decodable at the reference's size before
/// any work starts (FileError); a reference without texture in the region of interest is an InputError.
/// Testing aid: with the environment variable TRICOT_TEST_KILL_DIC_FRAME=k, the process kills itself
/// (SIGKILL) in the middle of writing frame k's rows.
DicRun run_dic(const DicSpec& spec, const std::vector<std::string>& images, const std::filesystem::path& out,
               const Log& log, const DicRunOptions& options = {});

/// One frame as a VTK grid for ParaView: the grid points at their reference positions (px, z = 0),
/// quads between neighbouring points, and point fields `displacement` (u, v, 0; NaN where not ok),
/// `exx`, `eyy`, `exy` (Green–Lagrange), `zncc` and `status` (dic::PointStatus as a number: 0 = ok;
/// its order in icgn.hpp). vsg_px > 0 (issue 16): the strains' virtual strain gauge as the field data
/// `vsg_px` (dic::virtual_strain_gauge).
io::VtuGrid fields_vtu(const std::vector<dic::GridPoint>& grid, const dic::TrackedFrame& frame, int vsg_px = 0);

/// DIR/points.csv's rows of one frame (its header aside): frame,id,x0,y0,x,y,u,v,zncc,status,exx,eyy,exy,
/// sigma_x,sigma_y (empty cells where there is no value).
std::string points_rows(const std::vector<dic::GridPoint>& grid, const dic::TrackedFrame& f);

}  // namespace tricot::project
