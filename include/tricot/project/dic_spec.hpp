// The config of `tricot dic` (THEORY §10): [dic] correlation and sequence settings, [strain] the strain
// fit, [physical] pixels → specimen millimetres, [output] what is written besides points.csv. Every key
// has a default, so a one-off run needs no file; command-line flags override the file (io::Node::set).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "tricot/dic/grid.hpp"
#include "tricot/dic/overlay.hpp"
#include "tricot/dic/physical.hpp"
#include "tricot/dic/sequence.hpp"
#include "tricot/io/config.hpp"

namespace tricot::project {

/// The whole file: [dic], [strain], [physical], [output].
io::SectionSpec dic_schema();

/// What the run writes besides DIR/points.csv and DIR/frames.csv.
struct DicOutputs {
  bool overlays = true;            ///< DIR/overlays/frame_NNNN.png
  dic::OverlayOptions overlay;
  bool increments = false;         ///< DIR/increments.csv (fixed-point incremental fields)
  std::optional<dic::PhysicalFrame> physical;  ///< DIR/specimen.csv when [physical] mm_per_px > 0
};

/// Everything `tricot dic` needs, built from a validated config.
struct DicSettings {
  dic::SequenceOptions sequence;
  dic::Roi roi;
  DicOutputs outputs;
};

/// Dotted keys set from the command line → the flag that set them ("dic.step" → "--step"), so that an
/// error about them names the flag rather than the file.
using FlagKeys = std::map<std::string, std::string>;

/// Builds the settings. `reference` is the first image (its size places the default specimen centre and
/// checks a mask); `config_dir` resolves a relative roi_mask path. Every library validate() error is
/// rethrown located at its key in the file (or at the flag that set it). Throws InputError/FileError.
DicSettings build_dic_settings(const io::Node& root, const image::Image& reference,
                               const std::filesystem::path& config_dir, const FlagKeys& flags = {});

/// Rethrows an error of the dic engine (key `dic.step`, `strain.window`, ...) at that key of `root`,
/// or at the flag that set it. Errors already located in a file are rethrown unchanged.
[[noreturn]] void rethrow_in_config(const io::Node& root, const InputError& e, const FlagKeys& flags = {});

/// Parses "X0,Y0,X1,Y1" (the --roi flag). Throws InputError (key --roi) when it is not four numbers.
io::Reals parse_roi_flag(const std::string& text);

}  // namespace tricot::project
