// `tricot synth` with [synth.lab] (src/project/pipeline/synth_lab.cpp): the raw lab record of a test — the
// LabVIEW-like load-cell log, the camera log, the relaxation log — against the FE truth it was made from.
#include "tricot/project/synth_lab.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "testing/cli.hpp"
#include "testing/experiment_case.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/log.hpp"
#include "tricot/project/experiment_files.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;
using test::scratch_dir;
using test::small_experiment;
using test::write_file;

// The log's force at an image instant (the images fall on its 10 ms grid: 2 s of lead, 0.5 s apart) is
// the truth plus the tare within 4 σ of the noise (99.99 % of draws); the cross-head likewise.
constexpr double kSigmas = 4;

fs::path synth_lab(const std::string& name, const std::string& lab_keys) {
  const fs::path dir = scratch_dir(name);
  write_file(
      dir / "experiment.toml",
      small_experiment("nx = 3\nny = 5\n\n[synth.images]\nenabled = true\npixel_size = 0.5\nwidth = 60\nheight = 60\n"
                       "subsamples = 1\n\n[synth.lab]\nenabled = true\n" +
                       lab_keys));
  const auto r = run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string() + " -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir / "exp" / "tension" / "lab";
}

TEST(SynthLab, WritesALabviewLogWhoseForceAtEachImageIsTheTruthPlusTheTare) {
  const fs::path lab = synth_lab("synth_lab_log", "");
  const io::LogTable log = io::read_log(lab / "load.txt");
  EXPECT_EQ(log.metadata.size(), 10u);
  EXPECT_EQ(log.format.delimiter, '\t');
  EXPECT_TRUE(log.format.decimal_comma);
  EXPECT_EQ(log.columns, (std::vector<std::string>{"Temps [s]", "Force [N]", "Traverse [mm]"}));
  const auto t = log.times("temps"), f = log.numbers("force"), c = log.numbers("traverse");
  EXPECT_NEAR(t[1] - t[0], 0.01, 1e-9);  // 100 Hz

  const auto truth = nlohmann::json::parse(io::read_text(lab / "truth.json"));
  const double delta = truth["clock_offset_s"], tare = truth["tare_N"], sigma = truth["force_noise_N"];
  EXPECT_DOUBLE_EQ(delta, 0.37);
  const auto frames = io::read_camera_log(lab / "camera.csv");
  const auto force = truth["force_N"].get<std::vector<double>>(), grip = truth["grip_mm"].get<std::vector<double>>();
  ASSERT_EQ(frames.size(), 11u);  // image 0 and the 10 steps
  // The synthetic experiment of the same run: its forces are the FE's (small_experiment is noise-free).
  const ident::TestData d = read_test_data(lab.parent_path().parent_path(), "tension", ident::FieldKind::cumulative);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (k > 0) {
      EXPECT_NEAR(force[k], d.edge_force[k - 1], 1e-9);
      EXPECT_NEAR(grip[k], d.edge_displacement[k - 1], 1e-9);
    }
    const double s = frames[k].time + delta;  // the image's instant on the log's clock
    const std::size_t i = std::size_t(std::lround(s / 0.01));
    ASSERT_LT(i, t.size());
    EXPECT_NEAR(t[i], s, 0.005);
    EXPECT_NEAR(f[i] - tare, force[k], kSigmas * sigma) << "image " << k;
    EXPECT_NEAR(c[i], 2 * grip[k], kSigmas * truth["crosshead_noise_mm"].get<double>()) << "image " << k;
  }
  // At rest before image 0, the log reads the tare.
  EXPECT_NEAR(f[0], tare, kSigmas * sigma);
  EXPECT_TRUE(fs::exists(lab / "relaxation.txt"));
}

TEST(SynthLab, WithoutCrossheadTheLogHasTwoColumns) {
  const fs::path lab = synth_lab("synth_lab_no_crosshead", "crosshead = false\nrelaxation = false\n");
  const io::LogTable log = io::read_log(lab / "load.txt");
  EXPECT_EQ(log.columns.size(), 2u);
  EXPECT_FALSE(fs::exists(lab / "relaxation.txt"));
}

TEST(SynthLab, OneAmplitudePerRelaxationTime) {
  const fs::path dir = scratch_dir("synth_lab_bad");
  write_file(
      dir / "experiment.toml",
      small_experiment("nx = 3\nny = 5\n\n[synth.images]\nenabled = true\npixel_size = 0.5\nwidth = 60\nheight = 60\n"
                       "subsamples = 1\n\n[synth.lab]\nenabled = true\nrelaxation_tau_s = [30.0, 360.0]\n"));
  const auto r = run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string() + " -q");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("synth.lab.relaxation_amplitudes_N"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace tricot::project
