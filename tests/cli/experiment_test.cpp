// tricot experiment LAB.toml -o DIR (apps/tricot/experiment.cpp, src/project/pipeline/lab_experiment.cpp): a
// synthetic lab record — rendered images of a uniaxial pull seen by a 2 fps camera, a 100 Hz load-cell
// log with 1 % noise, a tare and a clock offset of 0.37 s, written as a LabVIEW tab file with decimal
// commas and a 10-line header — turned into an experiment; and every bad input named in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "testing/cli.hpp"
#include "testing/experiment_case.hpp"
#include "testing/outputs.hpp"
#include "testing/paths.hpp"
#include "tricot/image/image.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/log.hpp"
#include "tricot/synth/lab_record.hpp"
#include "tricot/synth/speckle.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;
using test::scratch_dir;
using test::write_file;

// The issue's requirement for the recovered clock offset.
constexpr double kOffsetToleranceS = 0.010;
// Forces at image times: the log's noise σ (1 % of the peak) averaged over no samples (the instant),
// so each image's force is within 4 σ of the truth (99.99 %), plus the interpolation across the
// offset error (≤ 10 ms of a 0.85 N/s ramp: < 0.01 N).
constexpr double kForceSigmas = 4;
// Camera noise, fraction of full scale (as the lab engine's chain test).
constexpr double kImageNoise = 0.01;
constexpr int kSize = 200;         // px
constexpr double kMmPerPx = 0.25;  // 50 mm across the image
// forces.csv writes 9 significant digits.
constexpr double kCsvDigits = 1e-8;
// points.csv writes positions to 1e-5 px: a DIC folder read back gives the grip proxy to ~1e-5 px,
// hence the same δ and forces to ~1e-5 N.
constexpr double kReadBackN = 1e-4;

double fabric_force(double g) { return 1.5 * g + 0.03 * g * g * g; }

struct Lab {
  fs::path dir;
  synth::LabRecordOptions options;
  synth::LabRecord record;
};

// Renders the images of a uniaxial, isochoric stretch of a 40 × 50 mm specimen (the grip of the quarter
// is half the cross-head travel) and writes the LabVIEW log and the camera log.
Lab make_lab(const std::string& name, synth::LabRecordOptions o = {}) {
  Lab lab;
  lab.dir = scratch_dir(name);
  o.crosshead_travel_mm = 10;
  o.ramp_s = 6;  // 12 images of ramp at 2 fps, 3 s of rest and hold: 25 images
  lab.options = o;
  lab.record = synth::make_lab_record(o, fabric_force);
  synth::SpeckleOptions speckle;
  speckle.subsamples = 2;
  const synth::SpecklePattern pattern(speckle, -10, -10, kSize + 10, kSize + 10);
  const Vec2 c(0.5 * (kSize - 1), 0.5 * (kSize - 1));
  fs::create_directories(lab.dir / "images");
  std::vector<io::FrameTime> frames;
  for (std::size_t k = 0; k < lab.record.frame_time.size(); ++k) {
    const double ly = 1 + lab.record.grip_true[k] / 25.0, lx = 1 / std::sqrt(ly);
    const image::Image img = synth::add_noise(
        synth::render(pattern, kSize, kSize,
                      [&](const Vec2& x) { return Vec2(c(0) + (x(0) - c(0)) / lx, c(1) + (x(1) - c(1)) / ly); }),
        kImageNoise, 100 + k);
    const std::string file = fmt::format("img_{:04d}.png", k);
    io::write_atomic(lab.dir / "images" / file, image::encode_gray(img, ".png", 8));
    frames.push_back({file, lab.record.frame_time[k]});
  }
  io::write_atomic(lab.dir / "load.txt", io::to_log_text(synth::labview_log(lab.record, o)));
  io::write_atomic(lab.dir / "camera.csv", io::to_camera_log_text(frames));
  return lab;
}

// A lab file for make_lab's record; `test_keys` are added to (or replace, being later) the test's keys.
std::string lab_file(const std::string& test_keys = {}, const std::string& crosshead = "Traverse",
                     const std::string& physical = "mm_per_px = 0.25", double width_mm = 40) {
  return fmt::format(R"([experiment]
field_kind = "cumulative"
plot = false

[physical]
{}

[dic]
step = 15
roi = [52, 52, 147, 147]

[output]
overlays = false

[[test]]
name = "pull"
images = "images"
camera_log = "camera.csv"
log = "load.txt"
time_column = "Temps"
force_column = "Force"
crosshead_column = "{}"
width_mm = {}
free_length_mm = 50.0
{}
)",
                     physical, crosshead, width_mm, test_keys);
}

struct LabRun {
  test::CliRun cli;
  fs::path out;
};

LabRun experiment(const Lab& lab, const std::string& lab_text, const std::string& out_name = "out") {
  const fs::path file = write_file(lab.dir / "lab.toml", lab_text);
  const fs::path out = lab.dir / out_name;
  return {run_tricot("experiment " + file.string() + " -o " + out.string() + " -q"), out};
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(io::read_text(p)); }

// One record per process (rendering takes a second or two): the tests of a process share it, and its
// folder is the process's own, since ctest -j runs each test in a process of its own, side by side.
const Lab& shared_lab() {
  static const Lab lab = make_lab("experiment_shared_" + std::to_string(::getpid()));
  return lab;
}

TEST(Experiment, RecoversTheClockOffsetWithTheCrossheadAndGivesForcesWithinTheNoise) {
  const Lab& lab = shared_lab();
  const LabRun r = experiment(lab, lab_file(), "with_crosshead");
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.err;
  const auto j = read_json(r.out / "sync.json");
  EXPECT_EQ(j["pull"]["method"], "crosshead");
  EXPECT_NEAR(j["pull"]["clock_offset_s"].get<double>(), lab.options.clock_offset_s, kOffsetToleranceS);
  EXPECT_NEAR(j["pull"]["tare_N"].get<double>(), lab.options.tare_N, 3 * lab.record.force_noise_N);
  const io::Table f = io::read_csv(r.out / "pull" / "forces.csv");
  EXPECT_EQ(f.columns,
            (std::vector<std::string>{"step", "time", "load", "edge_displacement", "edge_force", "force_per_width"}));
  ASSERT_EQ(f.rows.size() + 1, lab.record.frame_time.size());
  for (std::size_t k = 0; k < f.rows.size(); ++k) {
    EXPECT_NEAR(f.rows[k][4], lab.record.force_true[k + 1], kForceSigmas * lab.record.force_noise_N)
        << "step " << k + 1;
    EXPECT_NEAR(f.rows[k][3], lab.record.grip_true[k + 1], 0.01) << "step " << k + 1;  // half the cross-head (σ 1 µm)
    EXPECT_NEAR(f.rows[k][5], f.rows[k][4] / 40.0, kCsvDigits * std::abs(f.rows[k][5]) + 1e-300);
  }
  EXPECT_TRUE(fs::exists(r.out / "project.toml"));
  EXPECT_TRUE(fs::exists(r.out / "pull" / "dic" / "points.csv"));
}

// Issue 14: a killed rerun of tricot experiment into a folder that holds another run (here synchronised
// from the cross-head, the rerun from the onset of motion) leaves that run whole; completed, only its own.
TEST(Experiment, AKilledRerunLeavesNoMix) {
  const Lab& lab = shared_lab();
  const fs::path root = scratch_dir("experiment_no_mix_" + std::to_string(::getpid()));
  const fs::path with = write_file(root / "with.toml", lab_file()),
                 without = write_file(root / "without.toml", lab_file({}, ""));
  // The lab file names its inputs relative to itself: the record lives in lab.dir.
  const auto relink = [&](const fs::path& f) {
    std::string t = io::read_text(f);
    for (const char* k : {"\"images\"", "\"camera.csv\"", "\"load.txt\""}) {
      const std::string name = std::string(k).substr(1, std::string(k).size() - 2);
      t.replace(t.find(k), std::string(k).size(), "\"" + (lab.dir / name).string() + "\"");
    }
    write_file(f, t);
  };
  relink(with), relink(without);
  test::expect_no_mix(
      "experiment", root, [&](const fs::path& o) { return "experiment " + with.string() + " -q -o " + o.string(); },
      [&](const fs::path& o) { return "experiment " + without.string() + " -q -o " + o.string(); });
}

TEST(Experiment, RecoversTheClockOffsetWithoutACrossheadFromTheOnsetOfMotion) {
  const Lab& lab = shared_lab();
  const LabRun r = experiment(lab, lab_file({}, ""), "without_crosshead");
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.err;
  const auto j = read_json(r.out / "sync.json");
  EXPECT_EQ(j["pull"]["method"], "onset");
  EXPECT_EQ(j["pull"]["grip"], "field");
  EXPECT_NEAR(j["pull"]["clock_offset_s"].get<double>(), lab.options.clock_offset_s, kOffsetToleranceS);
}

TEST(Experiment, WritesTheFieldInTheQuarterModelWithTheDicSigma) {
  const Lab& lab = shared_lab();
  const LabRun r = experiment(lab, lab_file(), "field");
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.err;
  const io::Table t = io::read_csv(r.out / "pull" / "field.csv");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"step", "id", "x", "y", "u", "v", "sigma_u", "sigma_v"}));
  ASSERT_FALSE(t.rows.empty());
  // Truth at the last step: v = (λy − 1)·Y, u = (λx − 1)·X in the quarter (X, Y ≥ 0 after folding).
  const double ly = 1 + lab.record.grip_true.back() / 25.0, lx = 1 / std::sqrt(ly);
  const double last = t.rows.back()[0];
  double e2 = 0, s2 = 0;
  int n = 0;
  for (const auto& row : t.rows) {
    EXPECT_GE(row[2], 0.0);
    EXPECT_GE(row[3], 0.0);
    EXPECT_GT(row[6], 0.0);
    if (row[0] != last) continue;
    e2 += std::pow(row[4] - (lx - 1) * row[2], 2) + std::pow(row[5] - (ly - 1) * row[3], 2);
    s2 += row[6] * row[6] + row[7] * row[7];
    ++n;
  }
  // The σ from IC-GN and the actual error agree to the lab engine's tolerance (±35 %).
  EXPECT_NEAR(std::sqrt(e2 / s2), 1.0, 0.35) << n << " points";
}

TEST(Experiment, ReusesATricotDicFolderAndWritesIncrementalFields) {
  const Lab& lab = shared_lab();
  const LabRun first = experiment(lab, lab_file() + "\n", "dic_source");
  ASSERT_EQ(first.cli.exit_code, 0) << first.cli.err;
  std::string text = lab_file("dic = \"dic_source/pull/dic\"");
  text.replace(text.find("images = \"images\"\n"), 18, "");
  text.replace(text.find("field_kind = \"cumulative\""), 25, "field_kind = \"incremental\"");
  const LabRun r = experiment(lab, text, "from_dic");
  // The first run did not write increments.csv (cumulative): the incremental kind says so.
  EXPECT_EQ(r.cli.exit_code, 2);
  EXPECT_NE(r.cli.err.find("increments"), std::string::npos) << r.cli.err;
  std::string cumulative = lab_file("dic = \"dic_source/pull/dic\"");
  cumulative.replace(cumulative.find("images = \"images\"\n"), 18, "");
  const LabRun c = experiment(lab, cumulative, "from_dic");
  ASSERT_EQ(c.cli.exit_code, 0) << c.cli.err;
  const io::Table a = io::read_csv(c.out / "pull" / "forces.csv"), b = io::read_csv(first.out / "pull" / "forces.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t k = 0; k < a.rows.size(); ++k)
    EXPECT_NEAR(a.rows[k][4], b.rows[k][4], kReadBackN) << "step " << k + 1;

  std::string inc = lab_file();
  inc.replace(inc.find("field_kind = \"cumulative\""), 25, "field_kind = \"incremental\"");
  const LabRun i = experiment(lab, inc, "incremental");
  ASSERT_EQ(i.cli.exit_code, 0) << i.cli.err;
  const io::Table t = io::read_csv(i.out / "pull" / "field.csv");
  // An increment between two images is a fraction of the cumulative displacement: v ≈ Δλy·Y.
  double worst = 0;
  for (const auto& row : t.rows) {
    const std::size_t k = std::size_t(row[0]);
    const double dly = (lab.record.grip_true[k] - lab.record.grip_true[k - 1]) / 25.0;
    worst = std::max(worst, std::abs(row[5] - dly * row[3] / (1 + lab.record.grip_true[k - 1] / 25.0)));
  }
  EXPECT_LT(worst, 0.02);  // mm: a few DIC σ (~3 µm) on increments of up to 0.25 mm
}

TEST(Experiment, ReadsACsvLogWithUnitsInTheHeader) {
  const Lab& lab = shared_lab();
  std::string csv = "time (s),Force [N],Crosshead [mm]\n";
  for (std::size_t i = 0; i < lab.record.log_time.size(); ++i)
    csv += fmt::format("{:.4f},{:.6f},{:.6f}\n", lab.record.log_time[i], lab.record.log_force[i],
                       lab.record.log_crosshead[i]);
  write_file(lab.dir / "load.csv", csv);
  std::string text = lab_file({}, "crosshead");
  for (auto [from, to] : {std::pair{"log = \"load.txt\"", "log = \"load.csv\""}, std::pair{"\"Temps\"", "\"time\""},
                          std::pair{"\"Force\"", "\"force\""}})
    text.replace(text.find(from), std::string(from).size(), to);
  const LabRun r = experiment(lab, text, "csv");
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.err;
  EXPECT_NEAR(read_json(r.out / "sync.json")["pull"]["clock_offset_s"].get<double>(), lab.options.clock_offset_s,
              kOffsetToleranceS);
}

// ---------------------------------------------------------------------------------------------------
// Bad inputs: one line on stderr, naming what is wrong, and the documented exit code.

void expect_one_line_error(const test::CliRun& r, int code, const std::string& needle) {
  EXPECT_EQ(r.exit_code, code) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(ExperimentErrors, AnUnknownColumnGetsADidYouMean) {
  std::string text = lab_file();
  text.replace(text.find("\"Force\""), 7, "\"Forse\"");
  expect_one_line_error(experiment(shared_lab(), text, "bad_column").cli, 2, "did you mean");
}

TEST(ExperimentErrors, ALogThatStopsBeforeTheLastImageNamesTheFirstFrameLeftOut) {
  const Lab& lab = shared_lab();
  const io::LogTable t = io::read_log(lab.dir / "load.txt");
  std::string text = io::read_text(lab.dir / "load.txt");
  // Cut the log 4 s before its end: the last images (2 s of tail, then 2 s = 4 images) are left out.
  const double cut = lab.record.log_time.back() - 4;
  std::string kept;
  std::size_t pos = 0;
  int line = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    const std::string l = text.substr(pos, end - pos + 1);
    ++line;
    const auto it = std::find(t.lines.begin(), t.lines.end(), line);
    if (it == t.lines.end() || lab.record.log_time[std::size_t(it - t.lines.begin())] <= cut) kept += l;
    pos = end + 1;
  }
  write_file(lab.dir / "short.txt", kept);
  std::size_t first_out = 0;
  while (lab.record.frame_time[first_out] + lab.options.clock_offset_s <= cut) ++first_out;
  std::string file = lab_file();
  file.replace(file.find("load.txt"), 8, "short.txt");
  expect_one_line_error(experiment(lab, file, "short").cli, 2, fmt::format("img_{:04d}.png", first_out));
}

TEST(ExperimentErrors, TimeThatGoesBackwardsNamesItsLine) {
  const Lab& lab = shared_lab();
  write_file(lab.dir / "backwards.csv", "time,force,crosshead\n0,0,0\n0.01,0,0\n0.005,0,0\n0.03,0,0\n0.04,0,0\n");
  std::string file = lab_file();
  file.replace(file.find("load.txt"), 8, "backwards.csv");
  for (auto [from, to] : {std::pair{"\"Temps\"", "\"time\""}, std::pair{"\"Force\"", "\"force\""},
                          std::pair{"\"Traverse\"", "\"crosshead\""}})
    file.replace(file.find(from), std::string(from).size(), to);
  expect_one_line_error(experiment(lab, file, "backwards").cli, 2, "backwards.csv:4");
}

TEST(ExperimentErrors, ATextOrNanRowNamesItsLineAndColumn) {
  const Lab& lab = shared_lab();
  for (const std::string bad : {"oops", "NaN"}) {
    write_file(lab.dir / "text.csv", "time,force,crosshead\n0,0,0\n0.01," + bad + ",0\n0.02,0,0\n0.03,0,0\n0.04,0,0\n");
    std::string file = lab_file();
    file.replace(file.find("load.txt"), 8, "text.csv");
    for (auto [from, to] : {std::pair{"\"Temps\"", "\"time\""}, std::pair{"\"Force\"", "\"force\""},
                            std::pair{"\"Traverse\"", "\"crosshead\""}})
      file.replace(file.find(from), std::string(from).size(), to);
    expect_one_line_error(experiment(lab, file, "text").cli, 2, "text.csv:3");
  }
}

// A copy of the shared images whose frame 5 is changed by `spoil` (it gets the path of img_0005.png).
fs::path spoiled_images(const std::string& name, const std::function<void(const fs::path&)>& spoil) {
  const Lab& lab = shared_lab();
  const fs::path dir = lab.dir / name;
  fs::remove_all(dir);
  fs::copy(lab.dir / "images", dir);
  spoil(dir / "img_0005.png");
  return dir;
}

std::string with_images(const std::string& folder) {
  std::string file = lab_file();
  file.replace(file.find("images = \"images\""), 17, "images = \"" + folder + "\"");
  return file;
}

TEST(ExperimentErrors, AMissingFrameInTheNumberingIsNamed) {
  spoiled_images("images_missing", [](const fs::path& p) { fs::remove(p); });
  expect_one_line_error(experiment(shared_lab(), with_images("images_missing"), "missing").cli, 3, "missing frame 5");
}

TEST(ExperimentErrors, AnUnreadableFrameIsNamed) {
  spoiled_images("images_unreadable", [](const fs::path& p) { write_file(p, "not a png"); });
  expect_one_line_error(experiment(shared_lab(), with_images("images_unreadable"), "unreadable").cli, 3,
                        "img_0005.png");
}

TEST(ExperimentErrors, AFrameOfAnotherSizeIsNamed) {
  spoiled_images("images_size", [](const fs::path& p) {
    image::Image small(kSize / 2, kSize / 2);
    io::write_atomic(p, image::encode_gray(small, ".png", 8));
  });
  expect_one_line_error(experiment(shared_lab(), with_images("images_size"), "size").cli, 3, "img_0005.png");
}

TEST(ExperimentErrors, AScaleOfZeroIsNamed) {
  expect_one_line_error(experiment(shared_lab(), lab_file({}, "Traverse", "mm_per_px = 0.0"), "scale").cli, 2,
                        "physical.mm_per_px");
}

TEST(Experiment, CountsThePointsOutsideTheSpecimenInsteadOfDroppingThemSilently) {
  // A 16 mm wide specimen: the ROI's points beyond |X| = 8 mm lie outside it.
  const LabRun r = experiment(shared_lab(), lab_file({}, "Traverse", "mm_per_px = 0.25", 16), "outside");
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.err;
  const auto j = read_json(r.out / "sync.json");
  const int outside = j["pull"]["points_outside"].get<int>(), kept = j["pull"]["points"].get<int>();
  // The ROI [52, 147]² at step 15 holds 7 × 7 centres at x = 52, 67, …, 142 px, i.e. X = 0.25 (x − 99.5)
  // = −11.875, −8.125, −4.375, −0.625, 3.125, 6.875, 10.625 mm: three columns, 3 × 7 = 21 points, lie
  // beyond 8 mm; 28 are kept.
  EXPECT_EQ(outside, 21);
  EXPECT_EQ(kept, 28);
  EXPECT_NE(r.cli.out.find("outside"), std::string::npos) << r.cli.out;
}

}  // namespace
}  // namespace tricot::project
