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

/// [dic] besides the engine's keys (which dic::IcgnOptions, dic::DicOptions and dic::SequenceOptions
/// declare): the region of interest and the seeds, checked against the reference image.
struct DicTable {
  io::Reals roi;          ///< [x0, y0, x1, y1] px; [] = the whole image
  io::Reals roi_polygon;  ///< [x0, y0, x1, y1, x2, y2, ...] px
  std::string roi_mask;   ///< mask image, relative to the config's folder
  io::Reals seeds;        ///< [x0, y0, x1, y1, ...] px; [] = nearest the ROI centre
  Origin origin{"dic"};

  static auto keys() {
    using O = DicTable;
    return std::tuple{
        option(&O::roi, "dic.roi", "Region of interest: [x0, y0, x1, y1] px, a rectangle; [] = the whole image."),
        option(&O::roi_polygon, "dic.roi_polygon",
               "Region of interest as a polygon: [x0, y0, x1, y1, x2, y2, ...] px (at least 3 vertices)."),
        option(&O::roi_mask, "dic.roi_mask",
               "Region of interest as a mask image (same size as the reference; white = inside), relative to this "
               "file."),
        option(&O::seeds, "dic.seeds",
               "Seed points [x0, y0, x1, y1, ...] px in the reference image; [] = the point nearest the ROI centre.")};
  }
};

/// [physical]: specimen coordinates (dic::PhysicalFrame); mm_per_px = 0 writes no specimen.csv.
struct PhysicalTable {
  double mm_per_px = 0;
  io::Reals centre_px;  ///< [x, y] px; [] = the image centre
  double angle_deg = 0;
  bool y_up = true;
  Origin origin{"physical"};

  static auto keys() {
    using O = PhysicalTable;
    return std::tuple{
        option(&O::mm_per_px, "physical.mm_per_px", "Pixel size in mm; 0 = no specimen.csv.", 0, 1e6),
        option(&O::centre_px, "physical.centre_px",
               "[x, y] px: the specimen centre in the images; [] = the image centre."),
        option(&O::angle_deg, "physical.angle_deg",
               "Specimen X axis, counter-clockwise on screen from the image x axis, degrees.", -360, 360),
        option(&O::y_up, "physical.y_up", "The specimen Y axis points up on screen (image y points down).")};
  }
};

/// [output] besides the overlays' own keys (dic::OverlayOptions): what is written besides points.csv
/// and frames.csv.
struct OutputTable {
  bool overlays = true;
  int overlay_every = 10;
  io::Strings panels{"displacement", "exx", "eyy", "zncc"};
  bool increments = false;
  bool fields = true;
  int fields_every = 1;
  Origin origin{"output"};

  static auto keys() {
    using O = OutputTable;
    return std::tuple{
        option(&O::overlays, "output.overlays",
               "DIR/overlays/frame_NNNN.png: maps drawn over the images (see overlay_every)."),
        option(&O::overlay_every, "output.overlay_every",
               "An overlay of frame 0, of every n-th frame and of the last (1 = every frame; drawing costs time).", 1,
               1000000),
        option(&O::panels, "output.panels",
               "Maps in each overlay, two per row: displacement, u, v, exx, eyy, exy, zncc."),
        option(&O::increments, "output.increments",
               "DIR/increments.csv: displacement between consecutive images at the fixed grid centres\n(the paper's "
               "WIMA-style incremental fields; costs a second correlation per image)."),
        option(&O::fields, "output.fields",
               "DIR/fields/frame_NNNN.vtu (compressed binary: u, v, strains, ZNCC, status on the reference grid)\n"
               "and DIR/fields.pvd, the series ParaView opens (see fields_every)."),
        option(&O::fields_every, "output.fields_every",
               "Fields of frame 0, of every n-th frame and of the last (1 = every frame).", 1, 1000000)};
  }
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

/// The whole file. The engine's options are held as the engine takes them, each key declared once by
/// the options that hold it (core/options.hpp); the tables above hold the verb's own keys.
struct DicSpec {
  /// [dic] and [strain]: the engine's keys, at the verb's defaults (order = "auto").
  dic::SequenceOptions sequence = verb_defaults();
  DicTable dic;
  Origin strain{"strain"};
  PhysicalTable physical;
  dic::OverlayOptions overlay;  ///< [output] panel_width and zncc_floor (panels come from output.panels)
  OutputTable output;
  std::filesystem::path dir;  ///< the config's folder: a relative roi_mask is found there

  /// The engine's options as `tricot dic` starts from them: second order where it pays.
  static dic::SequenceOptions verb_defaults();

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

/// The schema of the file: [dic], [strain], [physical], [output], generated from the keys the options
/// declare, defaults from DicSpec{}.
io::SectionSpec dic_schema();

/// Parses "X0,Y0,X1,Y1" (the --roi flag). Throws InputError (key --roi) when it is not four numbers.
io::Reals parse_roi_flag(const std::string& text);

}  // namespace tricot::project
