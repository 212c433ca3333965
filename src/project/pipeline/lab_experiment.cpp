// tricot experiment: a lab's raw files → an experiment folder (see lab_experiment.hpp).
#include "tricot/project/lab_experiment.hpp"

#include "tricot/project/output_dir.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <string_view>
#include <nlohmann/json.hpp>

#include "output/plot.hpp"
#include "tricot/core/error.hpp"
#include "tricot/ident/problem.hpp"
#include "tricot/image/image.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/log.hpp"
#include "tricot/lab/specimen.hpp"
#include "tricot/project/dic_run.hpp"
#include "tricot/project/dic_spec.hpp"
#include "tricot/project/experiment_files.hpp"
#include "tricot/project/lab_tracks.hpp"

namespace tricot::project {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

// A column of a `tricot dic` table that may be absent or hold empty cells (a lost point): NaN there.
std::vector<double> optional_numbers(const io::LogTable& t, const char* column) {
  return t.has_column(column) ? t.numbers_or_empty(column) : std::vector<double>(t.rows(), NAN);
}

std::string num(double v) { return fmt::format("{:.9g}", v); }

bool is_image(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e == ".png" || e == ".tif" || e == ".tiff" || e == ".bmp";
}

// The last run of digits in a file's stem, or −1.
long frame_number(const fs::path& p) {
  const std::string s = p.stem().string();
  std::size_t end = s.find_last_of("0123456789");
  if (end == std::string::npos) return -1;
  std::size_t begin = end;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(s[begin - 1]))) --begin;
  if (end - begin > 9) return -1;
  return std::stol(s.substr(begin, end - begin + 1));
}

// Frame times (camera clock) of the images, by the test's source.
std::vector<double> image_times(const LabTestSpec& t, const std::vector<std::string>& names) {
  std::vector<double> times;
  if (t.frame_times == "fps") return lab::frame_times(static_cast<int>(names.size()), t.fps, t.start_s);
  if (t.frame_times == "file_names") {
    for (const auto& n : names) times.push_back(io::time_from_file_name(fs::path(n).filename().string()));
  } else {
    const fs::path& log = t.camera_log;
    const auto frames = io::read_camera_log(log, t.camera_file_column, t.camera_time_column);
    std::map<std::string, double> by_name;
    for (const auto& f : frames) by_name[fs::path(f.file).filename().string()] = f.time;
    for (const auto& n : names) {
      const auto it = by_name.find(fs::path(n).filename().string());
      if (it == by_name.end())
        throw InputError({log.string(), 0, t.camera_file_column},
                         "no time for image " + fs::path(n).filename().string(), "", "a row for every image");
      times.push_back(it->second);
    }
  }
  for (std::size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1]))
      throw InputError(t.origin.where("frame_times"),
                       "frame time goes backwards at " + fs::path(names[k]).filename().string(),
                       num(times[k]) + " s after " + num(times[k - 1]) + " s", "increasing times");
  return times;
}

lab::LoadLog load_log(const LabTestSpec& t) {
  const io::LogTable table = io::read_log(t.log);
  lab::LoadLog log;
  log.source = t.log.string();
  log.time = table.times(t.time_column);
  log.force = table.numbers(t.force_column);
  if (!t.crosshead_column.empty()) log.crosshead = table.numbers(t.crosshead_column);
  return log;
}

// The FE load of each step: the force or the quarter's grip displacement; a full model's are its
// steps' frames (labels: its boundaries carry the motion).
std::vector<double> fe_loads(const std::vector<lab::ForceStep>& steps, const ExperimentSpec& e,
                             const std::vector<long>& frames = {}) {
  std::vector<double> loads;
  for (std::size_t k = 0; k < steps.size(); ++k)
    loads.push_back(e.full() ? double(frames.at(k)) : e.force_control() ? steps[k].force_N : steps[k].grip_mm);
  return loads;
}

// forces.csv, through the one CSV writer (io::to_csv, as tricot synth's): `loads` (one per step) is
// the FE load column (fe_loads); the time and the force per width come after synth's columns' names.
void write_forces(const fs::path& file, const std::vector<lab::ForceStep>& steps, const std::vector<double>& loads) {
  io::Table t;
  t.columns = {"step", "time", "load", "edge_displacement", "edge_force", "force_per_width"};
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const lab::ForceStep& f = steps[k];
    t.rows.push_back({double(f.step), f.time_s, loads[k], f.grip_mm, f.force_N, f.force_per_width});
  }
  io::write_atomic(file, io::to_csv(t));
}

// field.csv, through the same writer, with each value's σ.
void write_field(const fs::path& file, const lab::QuarterField& q) {
  io::Table t;
  t.columns = {"step", "id", "x", "y", "u", "v", "sigma_u", "sigma_v"};
  for (Eigen::Index k = 0; k < q.u.rows(); ++k)
    for (std::size_t p = 0; p < q.point_ids.size(); ++p) {
      const auto a = static_cast<Eigen::Index>(p);
      t.rows.push_back({double(k + 1), double(q.point_ids[p]), q.X[p](0), q.X[p](1), q.u(k, a), q.v(k, a),
                        q.sigma_u(k, a), q.sigma_v(k, a)});
    }
  io::write_atomic(file, io::to_csv(t));
}

// sync.png's data: two columns `x`, `y` to 9 digits.
std::string sync_csv(const std::vector<std::string>& columns, const std::vector<double>& x,
                     const std::vector<double>& y) {
  constexpr io::CsvFormat kDigits = io::CsvFormat::significant(9);
  io::CsvWriter csv;
  csv.row(columns);
  for (std::size_t i = 0; i < x.size(); ++i) csv.number(x[i], kDigits).number(y[i], kDigits).end_row();
  return csv.take();
}

void write_sync_data(const fs::path& dir, const lab::LoadLog& log, const lab::SyncResult& s) {
  std::vector<double> force = log.force;
  for (double& f : force) f -= s.tare_N;
  io::write_atomic(dir / "sync_log.csv", sync_csv({"log_time", "force"}, log.time, force));
  io::write_atomic(dir / "sync_images.csv", sync_csv({"log_time", "force"}, s.log_time, s.force));
  io::write_atomic(dir / "sync_criterion.csv", sync_csv({"lag_s", "criterion"}, s.lag_s, s.correlation));
}

void plot_sync(const fs::path& out, const std::vector<LabTestResult>& tests, const Log& log) {
  std::string script = fmt::format("set multiplot layout {},2\n", tests.size());
  for (const auto& t : tests) {
    const fs::path d = out / t.name;
    script += fmt::format(
        "set title \"{0}: force (tare removed) vs load-cell time; images at t_k + δ, δ = {1:.4f} s\"\nset xlabel \"log "
        "time (s)\"\n"
        "set ylabel \"force (N)\"\nset key top left\n"
        "plot {2} using 1:2 with lines lc rgb \"#888888\" title \"load cell\", {3} using 1:2 with points pt 7 ps 0.8 "
        "lc rgb \"#d62728\" title \"images\"\n",
        t.name, t.sync.clock_offset_s, io::gnuplot_quote(d / "sync_log.csv"), io::gnuplot_quote(d / "sync_images.csv"));
    if (t.sync.lag_s.empty()) script += "set title \"offset given\"\nunset key\nplot 0 notitle\n";
    else
      script += fmt::format(
          "set title \"{0}: {1} criterion near its optimum\"\nset xlabel \"lag δ (s)\"\nset ylabel \"1 − |{2}|\"\n"
          "set logscale y\nset xrange [{3} - 1:{3} + 1]\nset arrow 1 from {3},graph 0 to {3},graph 1 nohead dt 2\n"
          "plot {4} using 1:(1 - abs($2) + 1e-12) with lines lw 2 title \"criterion\"\nunset arrow 1\nunset logscale "
          "y\nset xrange [*:*]\n",
          t.name, lab::to_string(t.sync.method), t.sync.method == lab::SyncMethod::crosshead ? "correlation r" : "R²",
          t.sync.clock_offset_s, io::gnuplot_quote(d / "sync_criterion.csv"));
  }
  script += "unset multiplot\n";
  plot({.png = out / "sync.png",
        .width = 1000,
        .height = 380 * static_cast<int>(tests.size()),
        .font_size = 10,
        .name = "sync.png"},
       script, log);
}

// A rig test's set, hold, pull (lab_schema(): setting_images, hold_images): δ from the pull and the
// rest before it (the last setting image and the hold images: the cross-head at rest, then moving;
// the setting images before them move the field but not the cross-head, so they are left out), the
// tare from the log before image 0 (the setting loads the cell), then every image's force with both.
lab::SyncResult synchronise_set_hold_pull(const lab::LoadLog& load, const lab::ImageTimes& images,
                                          std::size_t last_setting, const lab::SyncOptions& options,
                                          const LabTestSpec& t) {
  lab::ImageTimes pull;
  for (std::size_t k = last_setting; k < images.time.size(); ++k) {
    pull.time.push_back(images.time[k]);
    pull.grip.push_back(images.grip[k] - images.grip[last_setting]);
    if (!images.names.empty()) pull.names.push_back(images.names[k]);
  }
  const lab::SyncResult p = lab::synchronise(load, pull, options);
  lab::SyncOptions given = options;
  given.clock_offset_s = p.clock_offset_s;
  int samples = 0;
  if (!options.tare_N) {
    const double until = images.time.front() + p.clock_offset_s - options.tare_margin_s;
    double sum = 0;
    for (std::size_t i = 0; i < load.time.size() && load.time[i] < until; ++i) sum += load.force[i], ++samples;
    if (samples == 0)
      t.origin.fail("log", "the log starts after image 0, so the force at rest before the setting is unknown",
                    num(load.time.front()) + " s",
                    fmt::format("a log from before {} s (image 0), or tare_N", num(until)));
    given.tare_N = sum / samples;
  }
  lab::SyncResult all = lab::synchronise(load, images, given);
  all.method = p.method;
  all.termination = p.termination;
  all.lag_s = p.lag_s;
  all.correlation = p.correlation;
  all.peak_correlation = p.peak_correlation;
  all.motion_onset_log_s = p.motion_onset_log_s;
  all.motion_onset_camera_s = p.motion_onset_camera_s;
  all.message = p.message;
  all.tare_given = options.tare_N.has_value();
  all.tare_samples = samples;
  return all;
}

}  // namespace

namespace {

std::string project_skeleton(const LabSpec& spec, const std::vector<LabTestResult>& tests, const fs::path& out) {
  const ExperimentSpec& e = spec.experiment;
  std::string s = fmt::format("# Written by `tricot experiment` from {}; then\n#   tricot identify {} -o OUT\n\n",
                              spec.file, (out / "project.toml").string());
  const fs::path& tpl = e.project_template;
  if (!tpl.empty()) {
    s += io::read_text(tpl) + "\n";
  } else {
    const LabTestSpec& t0 = spec.test.front();
    s += fmt::format(
        "[mesh]   # the quarter of the full specimen: width and height are the full sizes\nwidth = {}\nheight = {}\n"
        "element = \"Q8\"\nnx = 10\nny = 34\n\n",
        num(t0.width_mm), num(t0.free_length_mm));
    s += "[law]\ntype = \"mooney_rivlin\"   # choose the law\n\n[law.mooney_rivlin]\nterms = [\"C10\", \"C20\", "
         "\"C21\"]\n"
         "values = [0.05, -0.01, 0.005]   # the start point\n\n";
    s += fmt::format(
        "[[parameter]]\nname = \"C10\"\n[[parameter]]\nname = \"C20\"\n[[parameter]]\nname = \"C21\"\n\n"
        "[data]\n{} = 1.0\nfield = 1.0\nfield_sigma = \"per_point\"   # the DIC's σ of every value (field.csv)\n\n",
        e.force_control() ? "edge_displacement" : "edge_force");
  }
  for (std::size_t i = 0; i < tests.size(); ++i) {
    s += project_test_table(spec.test[i], tests[i], e);
    if (spec.test[i].force_scale)
      s += fmt::format(
          "[[parameter]]   # {0}'s specimen against the law's (force_scale in the lab file)\nname = \"{0}.{1}\"\n\n",
          tests[i].name, ident::kForceScale);
  }
  s += fmt::format("[experiment]\ndir = \".\"\nfield_kind = \"{}\"\n", e.field_kind);
  double noise = 0;
  for (const auto& t : tests) noise = std::max(noise, t.force_noise_N);
  if (e.sigma_edge_force > 0)
    s += "sigma_edge_force = " + num(e.sigma_edge_force) + "   # N: the load cell's (lab file)\n";
  else if (!e.force_control() && e.force_sigma && noise > 0)
    s += "sigma_edge_force = " + num(noise) + "   # N: the logs' largest spread at rest (sync.json force_noise_N)\n";
  if (e.sigma_edge_displacement > 0) s += "sigma_edge_displacement = " + num(e.sigma_edge_displacement) + "\n";
  return s;
}

}  // namespace

namespace {

// The value written after `key =` on a line of TOML lines ("" when no line sets the key), quotes removed.
std::optional<std::string> toml_line_value(const std::string& lines, std::string_view key) {
  std::size_t begin = 0;
  while (begin < lines.size()) {
    std::size_t end = lines.find('\n', begin);
    if (end == std::string::npos) end = lines.size();
    std::string line = lines.substr(begin, end - begin);
    begin = end + 1;
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line.compare(first, key.size(), key) != 0) continue;
    std::size_t at = first + key.size();
    while (at < line.size() && (line[at] == ' ' || line[at] == '\t')) ++at;
    if (at >= line.size() || line[at] != '=') continue;
    std::string v = line.substr(at + 1);
    if (const std::size_t hash = v.find('#'); hash != std::string::npos) v.resize(hash);
    v.erase(0, v.find_first_not_of(" \t\""));
    v.erase(v.find_last_not_of(" \t\"") + 1);
    return v;
  }
  return std::nullopt;
}

}  // namespace

std::string project_test_table(const LabTestSpec& t, const LabTestResult& r, const ExperimentSpec& e) {
  if (e.full()) {  // the model lines last: they may hold [[test.boundary]] tables
    std::string lines = t.model;
    if (!lines.empty() && lines.back() != '\n') lines += '\n';
    // With clamps: the specimen between them, for a generated mesh ([mesh] whole = true).
    const std::string mesh = r.free_length_mm > 0
                                 ? fmt::format(
                                       "[test.mesh]   # the test's own specimen: width, and the clamps' "
                                       "distance\nwidth = {}\nheight = {}\n",
                                       num(r.width_mm), num(r.free_length_mm))
                                 : "";
    return fmt::format(
        "[[test]]   # the whole specimen\nname = \"{}\"\n# loads: forces.csv (the steps' frames)\n{}{}\n", r.name,
        lines, mesh);
  }
  // `direction` sets the material's orientation (issue 29): wale = material_angle 0, course = 90 (and a
  // rig's `pull`). Model lines that set them too must agree, or a course test would silently be fitted
  // as a wale one.
  const std::string& model = t.model;
  const std::string& direction = t.direction;
  const bool course = direction == "course";
  const auto angle = toml_line_value(model, "material_angle");
  const auto pull = toml_line_value(model, "pull");
  if (angle) {
    double a = NAN;
    try {
      a = std::stod(*angle);
    } catch (const std::exception&) {}
    const double m = std::fmod(std::fabs(a), 180.0);
    if (!(std::fabs(m - (course ? 90.0 : 0.0)) < 1e-9 || (!course && std::fabs(m - 180.0) < 1e-9)))
      t.origin.fail("model", fmt::format("its material_angle contradicts direction = \"{}\"", direction),
                    "material_angle = " + *angle,
                    course ? "90 (or leave it out: direction sets it)" : "0 (or leave it out: direction sets it)");
  }
  if (pull && *pull != direction)
    t.origin.fail("model", fmt::format("its pull contradicts direction = \"{}\"", direction),
                  "pull = \"" + *pull + "\"", "\"" + direction + "\" (or leave it out: direction sets it)");
  std::string orientation;
  if (!angle) orientation += fmt::format("material_angle = {}   # direction = \"{}\"\n", course ? 90 : 0, direction);
  if (!pull) orientation += fmt::format("pull = \"{}\"\n", direction);
  // The loads are in forces.csv, which identify reads (issue 29); a rig test's list replaces its
  // uniform pull and is written, to the last bit of forces.csv's (identify checks that they agree).
  std::string loads = "# loads: forces.csv\n";
  if (toml_line_value(model, "kind").value_or("") == "rig") {
    loads = "loads = [";
    for (std::size_t k = 0; k < r.loads.size(); ++k) loads += (k ? ", " : "") + io::to_toml(r.loads[k]);
    loads += "]   # forces.csv\n";
  }
  std::string lines = model;
  if (!lines.empty() && lines.back() != '\n') lines += '\n';
  const std::string mesh = r.free_length_mm > 0 ? fmt::format(
                                                      "[test.mesh]   # the test's own specimen (tracks: free length "
                                                      "between its clamps)\nwidth = {}\nheight = {}\n",
                                                      num(r.width_mm), num(r.free_length_mm))
                                                : "";
  return fmt::format("[[test]]   # {} direction{}\nname = \"{}\"\n{}{}control = \"{}\"\n{}{}\n", direction,
                     t.guide_mm > 0 ? fmt::format(", guide {} mm", num(t.guide_mm)) : "", r.name, lines, orientation,
                     e.control, loads, mesh);
}

std::string project_test_table(const io::Node& test, const LabTestResult& r, const ExperimentSpec& e) {
  return project_test_table(LabTestSpec::from_config(test), r, e);
}

std::vector<fs::path> list_images(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw FileError({folder.string(), 0, ""}, "image folder not found");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (e.is_regular_file() && is_image(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.size() < 3)
    throw FileError({folder.string(), 0, ""}, fmt::format("{} images: a sequence needs at least 3", files.size()));
  for (std::size_t k = 1; k < files.size(); ++k) {
    const long a = frame_number(files[k - 1]), b = frame_number(files[k]);
    if (a >= 0 && b > a + 1)
      throw FileError({(folder / files[k].filename()).string(), 0, ""},
                      fmt::format("missing frame {}: the sequence jumps from {} to {}", a + 1,
                                  files[k - 1].filename().string(), files[k].filename().string()));
  }
  return files;
}

dic::SequenceResult read_dic_folder(const fs::path& dir, std::vector<std::string>* images) {
  const fs::path pf = dir / "points.csv";
  {
    std::error_code ec;
    if (!fs::exists(pf, ec)) throw FileError({pf.string(), 0, ""}, "not a `tricot dic` output folder (no points.csv)");
  }
  const io::LogTable t = io::read_log(pf, io::LogFormat{',', false, 1});
  const auto frame = t.numbers("frame"), id = t.numbers("id"), x0 = t.numbers("x0"), y0 = t.numbers("y0");
  const auto status = t.text("status");
  const auto col = [&](const char* c) { return optional_numbers(t, c); };
  const auto x = col("x"), y = col("y"), sx = col("sigma_x"), sy = col("sigma_y"), zn = col("zncc");
  int frames = 0, points = 0;
  for (std::size_t i = 0; i < t.rows(); ++i)
    frames = std::max(frames, int(frame[i]) + 1), points = std::max(points, int(id[i]) + 1);
  dic::SequenceResult r;
  r.grid.resize(std::size_t(points));
  r.frames.resize(std::size_t(frames));
  for (int f = 0; f < frames; ++f) {
    auto& F = r.frames[std::size_t(f)];
    F.frame = f;
    F.x.assign(std::size_t(points), Vec2::Constant(NAN));
    F.sigma.assign(std::size_t(points), Vec2::Constant(NAN));
    F.zncc.assign(std::size_t(points), NAN);
    F.status.assign(std::size_t(points), dic::PointStatus::not_computed);
    F.strain.assign(std::size_t(points), dic::StrainPoint{});
  }
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const auto f = std::size_t(frame[i]), p = std::size_t(id[i]);
    r.grid[p].x = {x0[i], y0[i]};
    auto& F = r.frames[f];
    F.x[p] = {x[i], y[i]};
    F.sigma[p] = {sx[i], sy[i]};
    F.zncc[p] = zn[i];
    F.status[p] = status[i] == "ok" ? dic::PointStatus::ok : dic::PointStatus::lost;
    if (F.status[p] == dic::PointStatus::ok) ++F.ok;
  }
  const fs::path inc = dir / "increments.csv";
  std::error_code ec;
  if (fs::exists(inc, ec)) {
    const io::LogTable ti = io::read_log(inc, io::LogFormat{',', false, 1});
    const auto from = ti.numbers("from"), to = ti.numbers("to"), iid = ti.numbers("id");
    const auto st = ti.text("status");
    const auto icol = [&](const char* c) { return optional_numbers(ti, c); };
    const auto u = icol("u"), v = icol("v"), su = icol("sigma_x"), sv = icol("sigma_y");
    r.increments.resize(std::size_t(std::max(0, frames - 1)));
    for (int k = 0; k + 1 < frames; ++k) {
      auto& I = r.increments[std::size_t(k)];
      I.from = k, I.to = k + 1;
      I.u.assign(std::size_t(points), Vec2::Constant(NAN));
      I.sigma.assign(std::size_t(points), Vec2::Constant(NAN));
      I.zncc.assign(std::size_t(points), NAN);
      I.status.assign(std::size_t(points), dic::PointStatus::not_computed);
    }
    for (std::size_t i = 0; i < ti.rows(); ++i) {
      const int k = int(to[i]) - 1;
      if (k < 0 || k >= frames - 1 || int(from[i]) != k) continue;
      auto& I = r.increments[std::size_t(k)];
      const auto p = std::size_t(iid[i]);
      I.u[p] = {u[i], v[i]};
      I.sigma[p] = {su[i], sv[i]};
      I.status[p] = st[i] == "ok" ? dic::PointStatus::ok : dic::PointStatus::lost;
    }
  }
  if (images) {
    const io::LogTable tf = io::read_log(dir / "frames.csv", io::LogFormat{',', false, 1});
    *images = tf.text("image");
  }
  return r;
}

namespace {

// The force's noise σ in a per-frame record: its spread before the pull starts (the steps whose grip
// has not moved), and at least the reading's resolution / √12 (a gauge read to 0.01 N reads 0.00 at
// rest: its σ is not zero).
double frame_force_noise(const std::vector<lab::ForceStep>& steps, const std::vector<double>& all_forces) {
  std::vector<double> values = all_forces;
  std::sort(values.begin(), values.end());
  double resolution = 0;
  for (std::size_t i = 1; i < values.size(); ++i)
    if (double d = values[i] - values[i - 1]; d > 1e-12 && (resolution == 0 || d < resolution)) resolution = d;
  double s1 = 0, s2 = 0;
  int n = 0;
  const double peak =
      std::abs(steps.empty() ? 0.0 : std::max_element(steps.begin(), steps.end(), [](const auto& a, const auto& b) {
                                       return std::abs(a.grip_mm) < std::abs(b.grip_mm);
                                     })->grip_mm);
  for (const auto& f : steps)
    if (std::abs(f.grip_mm) <= 0.005 * peak) s1 += f.force_N, s2 += f.force_N * f.force_N, ++n;
  const double spread = n > 1 ? std::sqrt(std::max(0.0, (s2 - s1 * s1 / n) / (n - 1))) : 0.0;
  return std::max(spread, resolution / std::sqrt(12.0));
}

LabTestResult tracks_lab_test(const LabTestSpec& t, const LabPhysicalSpec& physical, const ExperimentSpec& e,
                              const fs::path& tdir, nlohmann::ordered_json& sync_json) {
  const std::string& name = t.name;
  const TracksTest tt = tracks_test(t, physical, e.full());
  LabTestResult r;
  r.loads = fe_loads(tt.steps, e, tt.step_frames);
  write_forces(tdir / kForcesFile, tt.steps, r.loads);
  write_field(tdir / kFieldFile, tt.field);
  if (!tt.clamp_motion
           .empty()) {  // the full model's clamps: series for [[test.boundary]] (series = "<test>/clamps.csv")
    std::vector<std::string> columns{"step"};
    for (const auto& m : tt.clamp_motion) columns.insert(columns.end(), {m.marker + "_ux", m.marker + "_uy"});
    constexpr io::CsvFormat kDigits = io::CsvFormat::significant(9);
    io::CsvWriter c;
    c.row(columns);
    for (std::size_t k = 0; k < tt.steps.size(); ++k) {
      c.integer(static_cast<long long>(k + 1));
      for (const auto& m : tt.clamp_motion) c.number(m.u[k](0), kDigits).number(m.u[k](1), kDigits);
      c.end_row();
    }
    io::write_atomic(tdir / "clamps.csv", c.take());
  }
  std::vector<double> all;
  for (const auto& f : tt.steps) all.push_back(f.force_N);
  r.name = name;
  r.sync.method = lab::SyncMethod::given;
  r.steps = static_cast<int>(tt.steps.size());
  r.points = static_cast<int>(tt.field.point_ids.size());
  r.outside = tt.field.outside, r.incomplete = tt.field.incomplete;
  // A full model without clamps knows no frame at rest (its grip is its boundaries'): no estimate.
  r.force_noise_N = e.full() && t.clamps.empty() ? 0.0 : frame_force_noise(tt.steps, all);
  if (!e.full() || tt.centred_on_clamps)
    r.width_mm = tt.geometry.width_mm, r.free_length_mm = tt.geometry.free_length_mm;
  sync_json[name] = {{"method", "frame_number"},
                     {"clock_offset_s", 0.0},
                     {"force_noise_N", r.force_noise_N},
                     {"reference_frame", tt.reference_frame},
                     {"step_frames", tt.step_frames},
                     {"mm_per_px", tt.mm_per_px},
                     {"free_length_mm", tt.geometry.free_length_mm},
                     {"width_mm", tt.geometry.width_mm},
                     {"rigid_motion_removed", tt.rigid_motion_removed},
                     {"points", tt.field.point_ids.size()},
                     {"points_outside", tt.field.outside},
                     {"points_incomplete", tt.field.incomplete},
                     {"report", tt.report}};
  // sync.png's data: the force per step (synchronised by frame number, no clock offset to find).
  std::vector<double> time, force;
  for (const auto& f : tt.steps) time.push_back(f.time_s), force.push_back(f.force_N);
  const std::string a = sync_csv({"log_time", "force"}, time, force);
  io::write_atomic(tdir / "sync_log.csv", a);
  io::write_atomic(tdir / "sync_images.csv", a);
  return r;
}

}  // namespace

LabExperimentResult run_lab_experiment(const LabSpec& spec, const fs::path& out, const Log& log) {
  spec.validate();
  const ExperimentSpec& e = spec.experiment;
  const auto& tests = spec.test;
  const lab::FieldKind kind = e.kind();
  LabExperimentResult result;
  json sync_json = json::object();
  OutputDir output(out, "experiment");  // written in staging, published at the end (issue 14)
  const fs::path staged = output.staging();
  const auto t_start = std::chrono::steady_clock::now();
  for (std::size_t ti = 0; ti < tests.size(); ++ti) {
    const LabTestSpec& t = tests[ti];
    const std::string& name = t.name;
    const fs::path tdir = staged / name;
    fs::create_directories(tdir);
    lab::SpecimenGeometry geometry{t.width_mm, t.free_length_mm, t.tolerance_mm};

    if (!t.tracks.empty()) {  // point tracks from another tool, the force per frame
      result.tests.push_back(tracks_lab_test(t, spec.physical, e, tdir, sync_json));
      log.print(fmt::format("{}: {}", name, sync_json[name]["report"].get<std::string>()));
      continue;
    }
    // The load-cell log first: a bad one fails before any DIC work.
    const lab::LoadLog load = load_log(t);
    load.validate();

    // The DIC sequence: run it, or read a `tricot dic` folder.
    dic::SequenceResult seq;
    std::vector<std::string> names;
    int width = 0, height = 0;
    if (!t.dic.empty()) {
      const fs::path& d = t.dic;
      seq = read_dic_folder(d, &names);
      const fs::path first = fs::path(names.front()).is_absolute() ? fs::path(names.front()) : d / names.front();
      std::error_code ec;
      if (fs::exists(first, ec)) {
        const image::LoadedImage ref = image::load_image(first);
        width = ref.image.width, height = ref.image.height;
      } else if (spec.physical.centre_px.empty()) {
        t.origin.fail("dic", "the reference image of the DIC folder is missing, so the specimen centre is unknown",
                      first.string(), "[physical] centre_px");
      }
    } else {
      const auto files = list_images(t.images);
      for (const auto& f : files) names.push_back(f.string());
      DicSpec dic_spec = spec.dic;
      dic_spec.output.increments = kind == lab::FieldKind::incremental;
      dic_spec.physical = spec.physical;
      dic_spec.physical.mm_per_px = 0;  // no specimen.csv: the experiment folder holds the field
      log.print(fmt::format("{}: DIC of {} images", name, names.size()));
      DicRun run = run_dic(dic_spec, names, tdir / "dic", log);
      for (const auto& w : run.warnings) log.print("  " + w);
      seq = std::move(run.result);
      const image::LoadedImage ref = image::load_image(names.front());
      width = ref.image.width, height = ref.image.height;
    }
    const dic::PhysicalFrame frame = spec.physical.frame(width, height);

    // Images: times and the grip motion the field shows.
    lab::ImageTimes images;
    images.names = names;
    images.time = image_times(t, names);
    if (images.time.size() != seq.frames.size())
      t.origin.fail("images", "the DIC holds another number of frames than the images",
                    std::to_string(seq.frames.size()), std::to_string(images.time.size()));
    const lab::QuarterField cumulative = lab::fold_sequence(seq, frame, geometry, lab::FieldKind::cumulative);
    if (cumulative.point_ids.empty())
      t.origin.fail("width_mm",
                    "no DIC point lies inside the specimen and is measured in every image: " + cumulative.report);
    images.grip = {0.0};  // image 0 is the unloaded reference; the field's steps are images 1..n−1
    for (double g : lab::grip_from_field(cumulative, geometry)) images.grip.push_back(g);

    const lab::SyncOptions sync_options = spec.sync.options(t);
    // A rig test's set, hold, pull: the steps are the pull's images only.
    const int setting = t.setting_images, hold = t.hold_images;
    const std::size_t first_pull = std::size_t(1 + setting + hold);  // the image of the pull's first step
    if (first_pull + 1 >= images.time.size())
      t.origin.fail(setting > 0 ? "setting_images" : "hold_images", "leaves fewer than two images of the pull",
                    fmt::format("{} setting + {} hold of {} images", setting, hold, images.time.size()),
                    fmt::format("at most {}", images.time.size() >= 3 ? images.time.size() - 3 : 0));
    const lab::SyncResult sync = first_pull > 1
                                     ? synchronise_set_hold_pull(load, images, std::size_t(setting), sync_options, t)
                                     : lab::synchronise(load, images, sync_options);

    // The force's noise σ: the spread of the log at rest (the samples the tare averages).
    double noise = 0;
    {
      const double until = first_pull > 1 ? images.time.front() + sync.clock_offset_s - sync_options.tare_margin_s
                           : std::isfinite(sync.motion_onset_log_s)
                               ? sync.motion_onset_log_s - sync_options.tare_margin_s
                               : load.time.front() + 0.1 * (load.time.back() - load.time.front());
      double s1 = 0, s2 = 0;
      int n = 0;
      for (std::size_t i = 0; i < load.time.size() && load.time[i] < until; ++i)
        s1 += load.force[i], s2 += load.force[i] * load.force[i], ++n;
      if (n > 1) noise = std::sqrt(std::max(0.0, (s2 - s1 * s1 / n) / (n - 1)));
    }
    std::vector<double> grip = images.grip;
    const std::string& grip_source = e.grip;
    if (grip_source == "crosshead" && !load.has_crosshead())
      e.origin.fail("grip", "grip = \"crosshead\" but the test's log has no cross-head column", name,
                    "crosshead_column set");
    if (grip_source != "field" && load.has_crosshead())
      for (std::size_t k = 0; k < grip.size(); ++k) grip[k] = 0.5 * sync.crosshead[k];
    std::vector<lab::ForceStep> steps;
    for (lab::ForceStep f : lab::force_steps(images, sync, grip, geometry.width_mm))
      if (f.step >= int(first_pull)) f.step -= int(first_pull) - 1, steps.push_back(f);
    const std::vector<double> loads = fe_loads(steps, e);
    write_forces(tdir / kForcesFile, steps, loads);

    lab::QuarterField field =
        kind == lab::FieldKind::cumulative ? cumulative : lab::fold_sequence(seq, frame, geometry, kind);
    if (first_pull > 1) {  // the setting and hold images are not steps (cumulative: from image 0 still)
      const Eigen::Index keep = field.u.rows() - Eigen::Index(first_pull - 1);
      field.u = field.u.bottomRows(keep).eval();
      field.v = field.v.bottomRows(keep).eval();
      field.sigma_u = field.sigma_u.bottomRows(keep).eval();
      field.sigma_v = field.sigma_v.bottomRows(keep).eval();
    }
    write_field(tdir / kFieldFile, field);
    write_sync_data(tdir, load, sync);

    LabTestResult r{name,
                    sync,
                    static_cast<int>(steps.size()),
                    static_cast<int>(field.point_ids.size()),
                    field.outside,
                    field.incomplete,
                    loads,
                    noise};
    sync_json[name] = {{"clock_offset_s", sync.clock_offset_s},
                       {"method", lab::to_string(sync.method)},
                       {"tare_N", sync.tare_N},
                       {"tare_given", sync.tare_given},
                       {"termination", sync.termination == lab::SyncTermination::found ? "found" : "at_search_limit"},
                       {"peak_correlation", sync.peak_correlation},
                       {"force_noise_N", noise},
                       {"images", images.time.size()},
                       {"setting_images", setting},
                       {"hold_images", hold},
                       {"first_step_image", first_pull},
                       {"grip", load.has_crosshead() && grip_source != "field" ? "crosshead" : "field"},
                       {"points", field.point_ids.size()},
                       {"points_outside", field.outside},
                       {"points_incomplete", field.incomplete}};
    log.print(fmt::format("{}: {}", name, sync.brief_report()));
    log.print(fmt::format("{}: {} steps, field {}: {}", name, steps.size(), e.field_kind, field.report));
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    log.reporter().report({"experiment", ti + 1, tests.size(),
                           fmt::format("test {} done, ETA {}", name,
                                       format_duration(elapsed / double(ti + 1) * double(tests.size() - ti - 1)))});
    result.tests.push_back(std::move(r));
  }
  io::write_atomic(staged / "sync.json", sync_json.dump(2) + "\n");
  if (e.plot) plot_sync(staged, result.tests, log);
  io::write_atomic(staged / "project.toml", project_skeleton(spec, result.tests, out));
  output.publish();
  log.print(fmt::format("wrote {}: {} test(s), sync.json, {}project.toml", out.string(), result.tests.size(),
                        e.plot ? "sync.png, " : ""));
  return result;
}

LabExperimentResult run_lab_experiment(const io::Node& root, const fs::path& out, const Log& log) {
  return run_lab_experiment(LabSpec::from_config(root), out, log);
}

}  // namespace tricot::project
