// The lab file of `tricot experiment` (lab_experiment.hpp): its schema and its typed spec, one struct
// per table whose fields are the table's TOML keys — [experiment], [sync], each [[test]], and the
// `tricot dic` tables [dic], [strain], [physical] (the camera, with a scale from two image points) and
// [output]. from_config reads every key once; LabSpec::validate() holds the checks across keys that
// the schema cannot make, each error at its key's file and line. The pipeline reads the spec only.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tricot/dic/physical.hpp"
#include "tricot/io/config.hpp"
#include "tricot/lab/specimen.hpp"
#include "tricot/lab/sync.hpp"
#include "tricot/project/dic_spec.hpp"
#include "tricot/project/spec.hpp"

namespace tricot::project {

/// The lab file: [experiment], [sync], [[test]] and the `tricot dic` tables ([dic], [strain],
/// [physical], [output]); defaults from the specs below.
io::SectionSpec lab_schema();

/// `[experiment]` of the lab file: what the experiment folder holds. The field names are the TOML keys
/// (help and ranges in lab_schema()).
struct ExperimentSpec {
  std::string field_kind = "cumulative";  ///< field.csv: cumulative or incremental
  std::string control = "displacement";   ///< forces.csv's load: displacement or force
  std::string grip = "auto";              ///< the grip displacement: auto, crosshead or field
  bool plot = true;                       ///< DIR/sync.png
  bool force_sigma = true;                ///< project.toml's sigma_edge_force from the logs' spread at rest
  double sigma_edge_displacement = 0;     ///< mm, ≥ 0: written to project.toml when > 0
  double sigma_edge_force = 0;            ///< N, ≥ 0: written to project.toml when > 0 (replaces the logs' spread)
  std::string model =
      "quarter";  ///< quarter (rigid motion removed with the clamps) or full (point tracks in the mesh frame)
  /// The project template, relative to the lab file's folder as written in the file ("" = a skeleton);
  /// from_config resolves it against that folder.
  std::filesystem::path project_template;
  Origin origin{"experiment"};

  static ExperimentSpec from_config(const io::Node& table);
  /// The one check: each word one of its choices, σ in its range. Throws InputError naming the key,
  /// the value and the range.
  void validate() const;
  lab::FieldKind kind() const {
    return field_kind == "incremental" ? lab::FieldKind::incremental : lab::FieldKind::cumulative;
  }
  bool force_control() const { return control == "force"; }
  bool full() const { return model == "full"; }
};

/// `[[test]]`: one test — its images (or a `tricot dic` folder, or point tracks made by another tool),
/// its frame times, its load-cell log and its specimen. The paths are resolved by from_config against
/// the lab file's folder ("" stays "": not given).
struct LabTestSpec {
  std::string name = "tension";
  std::filesystem::path images;  ///< folder of the numbered image sequence
  std::filesystem::path dic;     ///< or: a `tricot dic` output folder
  // Frame times.
  std::string frame_times = "camera_log";  ///< camera_log, fps or file_names
  std::filesystem::path camera_log;
  std::string camera_file_column = "file";
  std::string camera_time_column = "time";
  double fps = 0;
  double start_s = 0;
  // The load-cell log.
  std::filesystem::path log;
  std::string time_column = "time";
  std::string force_column = "force";
  std::string crosshead_column;          ///< "" = none (onset synchronisation)
  std::optional<double> clock_offset_s;  ///< given: used as is; unset: estimated
  std::optional<double> tare_N;          ///< given: used as is; unset: estimated
  // The specimen.
  double width_mm = 50;
  double free_length_mm = 200;
  bool free_length_mm_given = false;  ///< tracks with clamps: else the clamps' distance is the free length
  std::string direction = "wale";     ///< wale or course
  double guide_mm = 0;
  int setting_images = 0;  ///< a rig test's set, hold, pull: images that are not steps
  int hold_images = 0;
  double tolerance_mm = 0;
  // Point tracks (lab_tracks.hpp).
  std::filesystem::path tracks;
  std::string tracks_format = "long";  ///< long, wide or dice
  std::string tracks_unit = "px";      ///< px or mm
  bool tracks_unit_given = false;      ///< a header's unit must then agree with it
  std::string frame_column = "frame";
  std::string point_column = "point";
  std::string x_column = "x";
  std::string y_column = "y";
  std::filesystem::path frame_forces;
  io::Strings clamps;  ///< [A, B] or []
  io::Strings points;  ///< [] = every point but the clamps
  double sigma_tracks = 0.5;
  int frame_stride = 1;
  double mm_per_px = 0;  ///< the test's own scale; 0 = [physical]'s
  // DIR/project.toml.
  std::string model = "kind = \"uniaxial\"";  ///< TOML lines of the test's [[test]]
  bool force_scale = false;
  Origin origin{"test"};

  static LabTestSpec from_config(const io::Node& test);
};

/// `[sync]`: the load-cell synchronisation, lab::SyncOptions' fields (and defaults) less the per-test
/// clock_offset_s and tare_N.
struct SyncSpec {
  double max_offset_s = lab::SyncOptions{}.max_offset_s;
  double exposure_s = lab::SyncOptions{}.exposure_s;
  double onset_fraction = lab::SyncOptions{}.onset_fraction;
  int force_degree = lab::SyncOptions{}.force_degree;
  int crosshead_degree = lab::SyncOptions{}.crosshead_degree;
  double tare_margin_s = lab::SyncOptions{}.tare_margin_s;
  Origin origin{"sync"};

  static SyncSpec from_config(const io::Node& table);
  /// The engine's options for `test` (its clock_offset_s and tare_N when given).
  lab::SyncOptions options(const LabTestSpec& test) const;
};

/// `[physical]` of the lab file: the camera, `tricot dic`'s table plus the scale from two image points
/// a known distance apart.
struct LabPhysicalSpec : PhysicalTable {
  io::Reals scale_points;  ///< [x0, y0, x1, y1] px
  double scale_distance_mm = 0;
  bool mm_per_px_given = false;  ///< mm_per_px written: the scale, even beside scale_points
  bool scale_points_given = false;

  /// The pixel size, mm/px: mm_per_px, or from scale_points and scale_distance_mm. Throws InputError
  /// at the key that is wrong (a scale of zero, not four numbers, coincident points, ...).
  double scale() const;
  /// The camera's frame for images of `width` × `height` px (a validated spec: its centre is [] = the
  /// image centre, or two numbers).
  dic::PhysicalFrame frame(int width, int height) const;
};

/// The whole lab file.
struct LabSpec {
  ExperimentSpec experiment;
  SyncSpec sync;
  std::vector<LabTestSpec> test;
  /// [dic], [strain] and [output]: the DIC of a test of images, as `tricot dic` reads them. Its
  /// physical is left at its default: [physical] is the camera's, `physical`.
  DicSpec dic;
  LabPhysicalSpec physical;
  std::string file;  ///< the lab file ("" when built in code): project.toml names it
  Origin origin;

  /// From a file read with lab_schema() (or its defaults).
  static LabSpec from_config(const io::Node& root);
  /// The checks across keys: [experiment]'s, at least one test, and per test what its source needs
  /// (point tracks for a full model, their force file, two clamps; else the camera's scale and
  /// centre, the log, the images, the frame times, a cumulative field for setting images). Throws
  /// InputError at the key, in the file's order of the tests.
  void validate() const;
};

}  // namespace tricot::project
