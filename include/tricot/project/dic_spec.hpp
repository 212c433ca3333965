// The config of `tricot dic` (docs/theory.md §10): [dic] correlation and sequence settings, [strain] the strain
// fit, [physical] pixels → specimen millimetres, [output] what is written besides points.csv. Every key
// has a default, so a one-off run needs no file; command-line flags override the file's keys.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "tricot/dic/grid.hpp"
#include "tricot/dic/overlay.hpp"
#include "tricot/dic/physical.hpp"
#include "tricot/dic/sequence.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/spec.hpp"

namespace tricot::project {

/// [dic]: subsets, grid, correlation and sequence mode. Ranges: dic::IcgnOptions, dic::DicOptions and
/// dic::SequenceOptions::validate() (the schema repeats them for --print-config and the file).
struct DicTable {
  int subset_size = 31;              ///< px, odd, 7–301
  int step = 10;                     ///< px between subset centres, 1–1000
  std::string mode = "incremental";  ///< incremental, reference or auto
  std::string order = "auto";        ///< shape function: first, second or auto (issue 16; default auto)
  io::Reals roi;                     ///< [x0, y0, x1, y1] px; [] = the whole image
  io::Reals roi_polygon;             ///< [x0, y0, x1, y1, x2, y2, ...] px
  std::string roi_mask;              ///< mask image, relative to the config's folder
  io::Reals seeds;                   ///< [x0, y0, x1, y1, ...] px; [] = nearest the ROI centre
  int search_radius = 50;
  int max_seeds = 8;
  double seed_min_zncc = 0.9;
  int max_iterations = 50;
  double tolerance = 1e-3;
  double min_zncc = 0.7;
  double min_texture = 0.005;
  double prefilter_sigma = 0;
  double weight_sigma = 0;  ///< px: Gaussian window of the subsets, 0 = uniform (issue 16)
  double update_zncc = 0.95;
  double update_loss = 0.02;
  int batch = 32;
  int threads = 0;
  Origin origin{"dic"};
};

/// [strain]: the least-squares plane fit of the Green–Lagrange strains (dic::StrainOptions).
struct StrainTable {
  int window = 5;  ///< grid points per side, odd, 3–51
  double min_fraction = 0.35;
  Origin origin{"strain"};
};

/// [physical]: specimen coordinates (dic::PhysicalFrame); mm_per_px = 0 writes no specimen.csv.
struct PhysicalTable {
  double mm_per_px = 0;
  io::Reals centre_px;  ///< [x, y] px; [] = the image centre
  double angle_deg = 0;
  bool y_up = true;
  Origin origin{"physical"};
};

/// [output]: what is written besides points.csv and frames.csv.
struct OutputTable {
  bool overlays = true;
  int overlay_every = 10;
  io::Strings panels{"displacement", "exx", "eyy", "zncc"};
  int panel_width = 800;
  double zncc_floor = 0.9;
  bool increments = false;
  bool fields = true;
  int fields_every = 1;
  Origin origin{"output"};
};

/// What the run writes besides DIR/points.csv and DIR/frames.csv.
struct DicOutputs {
  bool overlays = true;    ///< DIR/overlays/frame_NNNN.png
  int overlay_every = 10;  ///< of frame 0, every overlay_every-th frame and the last
  dic::OverlayOptions overlay;
  bool increments = false;                     ///< DIR/increments.csv (fixed-point incremental fields)
  bool fields = true;                          ///< DIR/fields/frame_NNNN.vtu and DIR/fields.pvd (ParaView)
  int fields_every = 1;                        ///< of frame 0, every fields_every-th frame and the last
  std::optional<dic::PhysicalFrame> physical;  ///< DIR/specimen.csv when [physical] mm_per_px > 0
};

/// Everything `tricot dic` needs, in the engine's types.
struct DicSettings {
  dic::SequenceOptions sequence;
  dic::Roi roi;
  DicOutputs outputs;
};

/// The whole file.
struct DicSpec {
  DicTable dic;
  StrainTable strain;
  PhysicalTable physical;
  OutputTable output;
  std::filesystem::path dir;  ///< the config's folder: a relative roi_mask is found there

  /// From a file read with dic_schema() (or its defaults).
  static DicSpec from_config(const io::Node& root, std::filesystem::path dir = {});

  /// The engine's settings. `reference` is the first image (its size places the default specimen
  /// centre and checks a mask). Checks what spans keys here and every range through the engines'
  /// validate(), each error at its key's origin. Throws InputError (FileError for an unreadable mask).
  DicSettings settings(const image::Image& reference) const;

  /// Rethrows an engine's error (key `dic.step`, `strain.window`, ...) at that key's origin; an error
  /// no table owns is rethrown unchanged. Call it from a handler.
  [[noreturn]] void rethrow(const InputError& e) const;
};

/// The schema of the file: [dic], [strain], [physical], [output], defaults from DicSpec{}.
io::SectionSpec dic_schema();

/// Parses "X0,Y0,X1,Y1" (the --roi flag). Throws InputError (key --roi) when it is not four numbers.
io::Reals parse_roi_flag(const std::string& text);

}  // namespace tricot::project
