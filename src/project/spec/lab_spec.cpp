// The lab file of `tricot experiment`: its schema, its typed spec and the checks across its keys
// (lab_spec.hpp).
#include "tricot/project/lab_spec.hpp"

#include <fmt/format.h>

#include "spec/schema.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

namespace {

io::SectionSpec experiment_section() {
  const ExperimentSpec d;
  return io::SectionSpec{
      "experiment",
      "What the experiment folder holds.",
      false,
      {key("field_kind", d.field_kind,
           "field.csv: cumulative (material points tracked from image 0) or incremental (fixed points, "
           "displacement since the previous image; docs/theory.md §7).",
           -1e300, 1e300, {"cumulative", "incremental"}),
       key("control", d.control,
           "The FE load of each step in forces.csv: displacement (load = grip displacement of the quarter, mm) "
           "or force (load = the full specimen's force, N).",
           -1e300, 1e300, {"displacement", "force"}),
       key("grip", d.grip,
           "The grip displacement: crosshead (half the synchronised cross-head travel), field (from the DIC "
           "field, lab::grip_from_field) or auto (crosshead when the log has one).",
           -1e300, 1e300, {"auto", "crosshead", "field"}),
       key("plot", d.plot, "Write DIR/sync.png (gnuplot)."),
       key("force_sigma", d.force_sigma,
           "Write the logs' largest spread at rest to project.toml as sigma_edge_force (displacement control);\n"
           "false: leave it out, so that the force group is scaled by its RMS like the others."),
       key("sigma_edge_force", d.sigma_edge_force,
           "Written to project.toml's [experiment] when > 0: the load cell's σ, N (its specification), in place\n"
           "of the logs' spread at rest (force_sigma). A full model's tracks have no frames at rest: give it here.",
           0, 1e9),
       key("sigma_edge_displacement", d.sigma_edge_displacement,
           "Written to project.toml's [experiment] when > 0: the grip's σ, mm (half the cross-head's), so that\n"
           "every group has a measurement σ and the covariance is a real one (docs/theory.md §8).",
           0, 1e6),
       key("model", d.model,
           "The FE model of each test: quarter (the quarter specimen with two symmetry axes; a one-sided pull's\n"
           "rigid motion is removed with its clamps' mean displacement) or full (the whole specimen: point\n"
           "tracks only, every point where it is in the mesh frame, nothing removed; each [[test]]'s `model`\n"
           "lines give its kind = \"custom\" and [[test.boundary]] tables, its loads are the steps' frame\n"
           "numbers; docs/tutorial-own-specimen.md).",
           -1e300, 1e300, {"quarter", "full"}),
       key("project_template", d.project_template.string(),
           "A TOML file with the project's [mesh], [law], [[parameter]], [data], [identify] (no [[test]], no\n"
           "[experiment]): DIR/project.toml is it plus one [[test]] per test (loads from forces.csv) and\n"
           "[experiment]. \"\" = a skeleton to edit.")},
      {}};
}

// A path key, relative to the file's folder as written ("" stays "": not given).
fs::path beside_file(const Node& n, std::string_view key) {
  const fs::path p = n.string(key);
  if (p.empty() || p.is_absolute()) return p;
  return fs::path(n.file()).parent_path() / p;
}

std::string num(double v) { return fmt::format("{:.9g}", v); }

}  // namespace

ExperimentSpec ExperimentSpec::from_config(const io::Node& n) {
  ExperimentSpec e;
  e.field_kind = n.string("field_kind");
  e.control = n.string("control");
  e.grip = n.string("grip");
  e.plot = n.boolean("plot");
  e.force_sigma = n.boolean("force_sigma");
  e.sigma_edge_displacement = n.real("sigma_edge_displacement");
  e.sigma_edge_force = n.real("sigma_edge_force");
  e.model = n.string("model");
  e.project_template = beside_file(n, "project_template");
  e.origin = Origin(n);
  return e;
}

void ExperimentSpec::validate() const {
  const io::SectionSpec table = experiment_section();
  check_key(origin, table, "field_kind", field_kind);
  check_key(origin, table, "control", control);
  check_key(origin, table, "grip", grip);
  check_key(origin, table, "sigma_edge_displacement", sigma_edge_displacement);
  check_key(origin, table, "sigma_edge_force", sigma_edge_force);
  check_key(origin, table, "model", model);
  if (full() && force_control())
    origin.fail(
        "control",
        "a full model's boundaries carry the motion (its loads are the steps' frames): force control is the quarter's",
        "\"force\"", "\"displacement\"");
}

io::SectionSpec lab_schema() {
  const SyncSpec y0;
  const LabTestSpec t0;
  const LabPhysicalSpec p0;
  io::SectionSpec root{
      "", "tricot experiment: a lab's raw files → an experiment folder for `tricot identify`.", false, {}, {}};
  root.sections.push_back(experiment_section());
  root.sections.push_back(io::SectionSpec{
      "sync",
      "Load-cell synchronisation (lab::SyncOptions). Per test, clock_offset_s and tare_N override the estimates.",
      false,
      {key("max_offset_s", y0.max_offset_s, "Search range of the clock offset, s: |δ| ≤ max_offset_s.", 1e-6, 1e6),
       key("exposure_s", y0.exposure_s, "Exposure of each image, s: the force is averaged over it (0 = the instant).",
           0, 1e3),
       key("onset_fraction", y0.onset_fraction, "Onset method: fit up to this fraction of the travel, (0, 1].", 1e-3,
           1),
       key("force_degree", std::int64_t{y0.force_degree}, "Onset method: degree of the force–motion polynomial.", 1, 5),
       key("crosshead_degree", std::int64_t{y0.crosshead_degree},
           "Cross-head method: degree of the cross-head–grip polynomial (1 = affine, Pearson's r).", 1, 4),
       key("tare_margin_s", y0.tare_margin_s, "Log samples this close before the motion are left out of the tare, s.",
           0, 1e3)},
      {}});
  io::SectionSpec test{
      "test",
      "One test: its images (or a `tricot dic` output folder), its frame times, its load-cell log and its specimen.",
      true,
      {key("name", t0.name, "Folder name of the test in DIR (and [[test]] name in project.toml)."),
       key("images", t0.images.string(), "Folder of the numbered image sequence (.png, .tif, .bmp; image 0 unloaded)."),
       key("dic", t0.dic.string(),
           "Or: a `tricot dic` output folder to reuse (points.csv, frames.csv, increments.csv)."),
       key("frame_times", t0.frame_times,
           "Where frame times come from: camera_log (CSV of file and time), fps (fps and start_s) or "
           "file_names (`img_0003_t1.500s.tif`).",
           -1e300, 1e300, {"camera_log", "fps", "file_names"}),
       key("camera_log", t0.camera_log.string(), "The camera log (frame_times = camera_log)."),
       key("camera_file_column", t0.camera_file_column, "Its column of image file names."),
       key("camera_time_column", t0.camera_time_column, "Its column of times, s."),
       key("fps", t0.fps, "Frames per second (frame_times = fps), > 0.", 0, 1e6),
       key("start_s", t0.start_s, "Camera time of image 0, s (frame_times = fps)."),
       key("log", t0.log.string(), "The load-cell log (CSV or tab-separated; header lines, decimal comma, units)."),
       key("time_column", t0.time_column, "Its time column, s (names match ignoring case and units)."),
       key("force_column", t0.force_column, "Its force column, N."),
       key("crosshead_column", t0.crosshead_column, "Its cross-head column, mm; \"\" = none (onset synchronisation)."),
       key("clock_offset_s", 0.0,
           "When given: the clock offset (log − camera), s, used as is. Leave the key out to estimate it\n"
           "(a --print-config file lists it: delete the line)."),
       key("tare_N", 0.0, "When given: the force at rest, N, used as is. Leave the key out to estimate it."),
       key("width_mm", t0.width_mm, "Specimen width (full), mm.", 1e-9, 1e6),
       key("free_length_mm", t0.free_length_mm, "Free length between the clips (full), mm.", 1e-9, 1e6),
       key("direction", t0.direction, "Direction loaded: wale or course.", -1e300, 1e300, {"wale", "course"}),
       key("guide_mm", t0.guide_mm, "Guide setting of a biaxial-induced test, mm (0 = free edges).", 0, 1e6),
       key("setting_images", std::int64_t{t0.setting_images},
           "A rig test's images after image 0 that show the transverse dimension being set, the grip at rest\n"
           "(`tricot synth` camera.json: phase \"setting\"). They and the hold images are not steps: the steps\n"
           "are the pull's images. The clock offset comes from the last setting image, the hold and the pull\n"
           "(the cross-head at rest, then moving), the tare from the log before image 0. Cumulative fields only.",
           0, 1e6),
       key("hold_images", std::int64_t{t0.hold_images},
           "Images of the held setting after the setting images, before the pull (phase \"hold\").", 0, 1e6),
       key("tolerance_mm", t0.tolerance_mm, "DIC points up to this far beyond the outline count as inside, mm.", 0,
           1e6),
       key("tracks", t0.tracks.string(),
           "Or: point tracks made by another tool (lab_tracks.hpp): a CSV file (tracks_format long or wide) or\n"
           "the folder of DICe's DICe_solution_NNNN.txt files (dice). Needs frame_forces; no images, no log."),
       key("tracks_format", t0.tracks_format,
           "long: a row per point and frame (frame, point, x, y); wide: a row per frame (frame, <point>_x,\n"
           "<point>_y, ...); dice: DICe's solution files.",
           -1e300, 1e300, {"long", "wide", "dice"}),
       key("tracks_unit", t0.tracks_unit, "The tracks' positions: px (then a scale) or mm. Header units must agree.",
           -1e300, 1e300, {"px", "mm"}),
       key("frame_column", t0.frame_column, "The frame column of the tracks and of frame_forces."),
       key("point_column", t0.point_column, "The point-name column of long tracks."),
       key("x_column", t0.x_column, "The x column of long tracks (image axes)."),
       key("y_column", t0.y_column, "The y column of long tracks (image axes; y down)."),
       key("frame_forces", t0.frame_forces.string(),
           "A per-frame CSV that holds the force (frame_column, force_column), synchronised with the tracks\n"
           "by frame number: its frames must be the tracks'."),
       key("clamps", t0.clamps,
           "[A, B]: the tracked markers on the two clamps. The grip displacement is half the change of their\n"
           "distance along the pull, the free length their distance in the first frame (unless\n"
           "free_length_mm is given), and a one-sided pull's rigid motion is removed with their mean."),
       key("points", t0.points, "The tracked points that are the field (default: every point but the clamps)."),
       key("sigma_tracks", t0.sigma_tracks, "σ of a tracked position, in tracks_unit (field.csv's sigma_u, sigma_v).",
           0, 1e6),
       key("frame_stride", std::int64_t{t0.frame_stride},
           "Steps are every frame_stride-th frame after the first (the reference), and the last.", 1, 1000000),
       key("mm_per_px", t0.mm_per_px,
           "This test's pixel size, mm/px (a camera and zoom per test); 0 = [physical] mm_per_px.", 0, 1e6),
       key("model", t0.model,
           "TOML lines added to this test's [[test]] in DIR/project.toml (kind, grip_holds_x, mesh, ...)."),
       key("force_scale", t0.force_scale,
           "Identify this specimen's force scale k too (a [[parameter]] \"<name>.force_scale\" in\n"
           "DIR/project.toml; its model force is k times the law's): repeats of one fabric differ in stiffness.\n"
           "Leave it off on one test per direction, whose specimen sets the law's scale (docs/theory.md §2).")},
      {}};
  root.sections.push_back(test);
  for (io::SectionSpec s : dic_schema().sections) {
    if (s.name == "physical") {
      s.help = "The camera: scale (mm_per_px, or two image points a known distance apart), specimen centre, axes.";
      for (io::KeySpec& k : s.keys)
        if (k.name == "mm_per_px") k.help = "Pixel size, mm/px; 0 = from scale_points and scale_distance_mm.";
      s.keys.push_back(
          key("scale_points", p0.scale_points, "[x0, y0, x1, y1] px: two image points a known distance apart."));
      s.keys.push_back(key("scale_distance_mm", p0.scale_distance_mm, "Their distance, mm.", 0, 1e9));
    }
    root.sections.push_back(std::move(s));
  }
  return root;
}

SyncSpec SyncSpec::from_config(const io::Node& n) {
  SyncSpec y;
  y.max_offset_s = n.real("max_offset_s");
  y.exposure_s = n.real("exposure_s");
  y.onset_fraction = n.real("onset_fraction");
  y.force_degree = static_cast<int>(n.integer("force_degree"));
  y.crosshead_degree = static_cast<int>(n.integer("crosshead_degree"));
  y.tare_margin_s = n.real("tare_margin_s");
  y.origin = Origin(n);
  return y;
}

lab::SyncOptions SyncSpec::options(const LabTestSpec& test) const {
  lab::SyncOptions o;
  o.clock_offset_s = test.clock_offset_s;
  o.tare_N = test.tare_N;
  o.max_offset_s = max_offset_s;
  o.exposure_s = exposure_s;
  o.onset_fraction = onset_fraction;
  o.force_degree = force_degree;
  o.crosshead_degree = crosshead_degree;
  o.tare_margin_s = tare_margin_s;
  return o;
}

LabTestSpec LabTestSpec::from_config(const io::Node& n) {
  LabTestSpec t;
  t.name = n.string("name");
  t.images = beside_file(n, "images");
  t.dic = beside_file(n, "dic");
  t.frame_times = n.string("frame_times");
  t.camera_log = beside_file(n, "camera_log");
  t.camera_file_column = n.string("camera_file_column");
  t.camera_time_column = n.string("camera_time_column");
  t.fps = n.real("fps");
  t.start_s = n.real("start_s");
  t.log = beside_file(n, "log");
  t.time_column = n.string("time_column");
  t.force_column = n.string("force_column");
  t.crosshead_column = n.string("crosshead_column");
  if (n.given("clock_offset_s")) t.clock_offset_s = n.real("clock_offset_s");
  if (n.given("tare_N")) t.tare_N = n.real("tare_N");
  t.width_mm = n.real("width_mm");
  t.free_length_mm = n.real("free_length_mm");
  t.free_length_mm_given = n.given("free_length_mm");
  t.direction = n.string("direction");
  t.guide_mm = n.real("guide_mm");
  t.setting_images = static_cast<int>(n.integer("setting_images"));
  t.hold_images = static_cast<int>(n.integer("hold_images"));
  t.tolerance_mm = n.real("tolerance_mm");
  t.tracks = beside_file(n, "tracks");
  t.tracks_format = n.string("tracks_format");
  t.tracks_unit = n.string("tracks_unit");
  t.tracks_unit_given = n.given("tracks_unit");
  t.frame_column = n.string("frame_column");
  t.point_column = n.string("point_column");
  t.x_column = n.string("x_column");
  t.y_column = n.string("y_column");
  t.frame_forces = beside_file(n, "frame_forces");
  t.clamps = n.strings("clamps");
  t.points = n.strings("points");
  t.sigma_tracks = n.real("sigma_tracks");
  t.frame_stride = static_cast<int>(n.integer("frame_stride"));
  t.mm_per_px = n.real("mm_per_px");
  t.model = n.string("model");
  t.force_scale = n.boolean("force_scale");
  t.origin = Origin(n);
  return t;
}

double LabPhysicalSpec::scale() const {
  if (mm_per_px_given || !scale_points_given) {
    if (!(mm_per_px > 0))
      origin.fail("mm_per_px",
                  "a scale of zero: the pixel size must be > 0 (or give scale_points and scale_distance_mm)",
                  num(mm_per_px), "mm_per_px > 0");
    return mm_per_px;
  }
  const io::Reals& p = scale_points;
  if (p.size() != 4)
    origin.fail("scale_points", "two points are four numbers", std::to_string(p.size()) + " numbers",
                "[x0, y0, x1, y1]");
  try {
    return lab::scale_from_points({p[0], p[1]}, {p[2], p[3]}, scale_distance_mm);
  } catch (const InputError& e) {
    origin.fail(e.where().key.find("distance") != std::string::npos ? "scale_distance_mm" : "scale_points",
                e.problem());
  }
}

dic::PhysicalFrame LabPhysicalSpec::frame(int width, int height) const {
  dic::PhysicalFrame f;
  f.mm_per_px = scale();
  const io::Reals& c = centre_px;
  f.centre_px = c.size() == 2 ? Vec2(c[0], c[1]) : Vec2(0.5 * (width - 1), 0.5 * (height - 1));
  f.angle_deg = angle_deg;
  f.y_up = y_up;
  return f;
}

LabSpec LabSpec::from_config(const io::Node& root) {
  LabSpec x;
  x.experiment = ExperimentSpec::from_config(root.section("experiment"));
  x.sync = SyncSpec::from_config(root.section("sync"));
  for (const Node& t : root.array("test")) x.test.push_back(LabTestSpec::from_config(t));
  // `tricot dic`'s tables, read by its spec; [physical] is the camera, with the scale from two points.
  x.dic = DicSpec::from_config(root, fs::path(root.file()).parent_path());
  static_cast<PhysicalTable&>(x.physical) = x.dic.physical;
  x.dic.physical = {};
  const Node& ph = root.section("physical");
  x.physical.scale_points = ph.reals("scale_points");
  x.physical.scale_distance_mm = ph.real("scale_distance_mm");
  x.physical.mm_per_px_given = ph.given("mm_per_px");
  x.physical.scale_points_given = ph.given("scale_points");
  x.file = root.file();
  x.origin = Origin(root);
  return x;
}

void LabSpec::validate() const {
  experiment.validate();
  if (test.empty()) origin.fail("test", "no [[test]] table", "", "one [[test]] per test");
  bool camera_checked = false;  // [physical], with the first test that needs the camera
  for (const LabTestSpec& t : test) {
    const Origin& o = t.origin;
    if (experiment.full() && t.tracks.empty())
      o.fail("tracks", "model = \"full\" takes point tracks (e.g. `tricot dic`'s specimen.csv, tracks_unit = \"mm\")",
             "\"\"", "tracks = FILE");
    if (!t.tracks.empty()) {  // point tracks from another tool, the force per frame
      if (t.frame_forces.empty())
        o.fail("frame_forces", "a test of point tracks needs its per-frame force", "\"\"",
               "a CSV with a frame and a force column");
      if (t.tracks_format == "dice" && t.tracks_unit_given && t.tracks_unit != "px")
        o.fail("tracks_unit", "DICe's solutions are in px", "\"" + t.tracks_unit + "\"", "px");
      if (!t.clamps.empty() && t.clamps.size() != 2)
        o.fail("clamps", "two clamp markers: the fixed one and the pulled one",
               fmt::format("{} names", t.clamps.size()), "[A, B]");
      continue;
    }
    if (!camera_checked) {
      (void)physical.scale();
      const io::Reals& c = physical.centre_px;
      if (!c.empty() && c.size() != 2)
        physical.origin.fail("centre_px", "the centre is two numbers", std::to_string(c.size()) + " numbers",
                             "[x, y] or []");
      camera_checked = true;
    }
    if (t.log.empty()) o.fail("log", "a test needs its load-cell log", "\"\"", "a CSV or tab-separated file");
    if (t.dic.empty() && t.images.empty())
      o.fail("images", "a test needs its images or a `tricot dic` folder", "\"\"", "images = FOLDER or dic = FOLDER");
    if (t.frame_times == "fps" && !(t.fps > 0))
      o.fail("fps", "frame_times = \"fps\" needs a frame rate", num(t.fps), "fps > 0");
    if (t.frame_times == "camera_log" && t.camera_log.empty())
      o.fail("camera_log", "frame_times = \"camera_log\" needs the camera log", "\"\"", "a CSV file of file and time");
    if (t.setting_images + t.hold_images > 0 && experiment.kind() == lab::FieldKind::incremental)
      o.fail("setting_images",
             "an incremental field of a test with setting images is not supported (its first step "
             "would count from the held setting, the model's from the reference)",
             std::to_string(t.setting_images + t.hold_images), "field_kind = \"cumulative\"");
  }
}

}  // namespace tricot::project
