// examples/knit-uniaxial-real (issue 29): real knit data (../shared/data/knit-uniaxial, acrylic garter,
// five repeats along X and five along Y) from the raw CSVs to the report with TOML only: `tricot
// experiment` on the example's lab file, then `tricot identify` on the project it writes. The example
// reads ../shared relative to the repository root; the test copies it into a scratch tree laid out the
// same way, with the shared data linked in. Skipped when the shared data are not there.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "testing/cli.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/log.hpp"

namespace tricot {
namespace {

namespace fs = std::filesystem;

// Issue 29's targets: each repeat's force RMS within 3 % of its peak for the acrylic garter, 5 % for
// the cotton one, with every repeat of both directions identified jointly. Measured
// (docs/validation.md §4): 2.8 % and 3.1 % at worst, with each repeat but the first per direction
// given its own force scale (the repeats differ in stiffness by up to 22 %); without them the best
// single curve through the repeats is 5.4 % and 6.6 % off the worst one.
constexpr double kAcrylicForceRmsOfPeak = 0.03, kCottonForceRmsOfPeak = 0.05;

bool have_the_data() {
  return fs::exists(test::shared_data() / "knit-uniaxial" / "acrylic-garter-X" / "video1" / "tracks.csv");
}

// The example's lab file `lab` (with `templ`) in a scratch tree laid out as the repository, then
// `tricot experiment` and `tricot identify` into ROOT/out; returns ROOT.
fs::path run_example(const std::string& name, const char* lab, const char* templ) {
  const fs::path root = test::scratch_dir(name);
  const fs::path example = root / "repo" / "examples" / "knit-uniaxial-real";
  fs::create_directories(example);
  fs::create_directories(root / "shared");
  fs::create_directory_symlink(fs::absolute(test::shared_data()), root / "shared" / "data");
  for (const char* f : {lab, templ})
    fs::copy_file(test::source_dir() / "examples" / "knit-uniaxial-real" / f, example / f);
  const auto e =
      test::run_tricot("experiment " + (example / lab).string() + " -o " + (root / "experiment").string() + " -q");
  EXPECT_EQ(e.exit_code, 0) << e.err;
  const auto r = test::run_tricot("identify " + (root / "experiment" / "project.toml").string() + " -o " +
                                  (root / "out").string() + " -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return root;
}

// Each repeat's fit: its force RMS below `worst` of its peak (fit_<test>.csv, and as result.json says),
// its tracked points' residual (fit_field_<test>.csv, its RMS in result.json, its map in plots/), and
// the force scales of repeats 2–5 of each direction in result.json.
void expect_repeats_fitted(const fs::path& root, double worst) {
  const nlohmann::json j = nlohmann::json::parse(io::read_text(root / "out" / "result.json"));
  EXPECT_TRUE(j["converged"].get<bool>()) << j["termination"];
  EXPECT_TRUE(j["stability_passed"].get<bool>());
  EXPECT_TRUE(fs::exists(root / "out" / "report.html"));
  int tests = 0;
  for (const char* d : {"X", "Y"})
    for (int v = 1; v <= 5; ++v) {
      const std::string name = std::string(d) + std::to_string(v);
      const io::LogTable fit = io::read_log(root / "out" / ("fit_" + name + ".csv"));
      const auto model = fit.numbers("model_edge_force"), measured = fit.numbers("edge_force");
      double s2 = 0, peak = 0;
      for (std::size_t k = 0; k < model.size(); ++k)
        s2 += std::pow(model[k] - measured[k], 2), peak = std::max(peak, std::abs(measured[k]));
      EXPECT_LT(std::sqrt(s2 / double(model.size())), worst * peak) << name;
      EXPECT_NEAR(j["fit"][name]["force_rms_N"].get<double>(), std::sqrt(s2 / double(model.size())), 1e-9 * peak)
          << name;
      const io::LogTable field = io::read_log(root / "out" / ("fit_field_" + name + ".csv"));
      const auto u = field.numbers("u"), vv = field.numbers("v"), mu = field.numbers("model_u"),
                 mv = field.numbers("model_v");
      double e2 = 0;
      for (std::size_t k = 0; k < u.size(); ++k) e2 += std::pow(mu[k] - u[k], 2) + std::pow(mv[k] - vv[k], 2);
      EXPECT_NEAR(j["fit"][name]["points_rms_mm"].get<double>(), std::sqrt(e2 / double(u.size())), 1e-6) << name;
      EXPECT_TRUE(fs::exists(root / "out" / "plots" / ("fit_field_" + name + ".png"))) << name;
      EXPECT_EQ(j["parameters"].contains(name + ".force_scale"), v > 1) << name;
      ++tests;
    }
  EXPECT_EQ(tests, 10);
}

TEST(KnitUniaxialReal, AcrylicGarterFromTheRawCsvsToTheReportWithTomlOnly) {
  if (!have_the_data()) GTEST_SKIP() << "no " << test::shared_data() / "knit-uniaxial";
  const fs::path root = run_example("knit_uniaxial_real", "acrylic-garter.toml", "project-template.toml");
  expect_repeats_fitted(root, kAcrylicForceRmsOfPeak);
  // `tricot simulate --law result.json` replays each repeat with its force scale: X2's forces are the fit's.
  const auto replay =
      test::run_tricot("simulate " + (root / "experiment" / "project.toml").string() + " --law " +
                       (root / "out" / "result.json").string() + " -o " + (root / "replay").string() + " -q");
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  const auto replayed = io::read_log(root / "replay" / "X2" / "steps.csv").numbers("edge_force");
  const auto fitted = io::read_log(root / "out" / "fit_X2.csv").numbers("model_edge_force");
  ASSERT_EQ(replayed.size(), fitted.size());
  for (std::size_t k = 0; k < fitted.size(); ++k) EXPECT_NEAR(replayed[k], fitted[k], 1e-9 * fitted.back()) << k;
  // Five repeats per direction, all free-sided: one path through (εC, εW) per surface, so eq. 9 is
  // "not computed", with the counts (issue 29, obstacle 7).
  const nlohmann::json j = nlohmann::json::parse(io::read_text(root / "out" / "result.json"));
  for (const char* surface : {"course", "wale"}) {
    const auto& e = j["eq9"][surface];
    EXPECT_FALSE(e["computed"].get<bool>()) << surface;
    EXPECT_EQ(e["held_levels"].get<int>(), 1) << surface;
    EXPECT_GT(e["points_whole"].get<int>(), 50) << surface;
  }
}

TEST(KnitUniaxialReal, CottonGarterTheSameWay) {
  if (!have_the_data()) GTEST_SKIP() << "no " << test::shared_data() / "knit-uniaxial";
  expect_repeats_fitted(run_example("knit_uniaxial_cotton", "cotton-garter.toml", "project-template.toml"),
                        kCottonForceRmsOfPeak);
}

// The same repeats as whole specimens (acrylic-garter-full.toml: model = "full", each clamp driven by
// its marker's measured motion, nothing removed or folded). With one homogeneous material both models
// stretch the fabric uniformly between the clamps, so they leave the same residual on the tracked
// points (measured: full / quarter 0.99–1.00 per repeat, 1.0–2.9 mm): the quarter's rigid motion
// removal already follows the one-sided pull. Issue 29's "at most half the quarter's" is not reached.
TEST(KnitUniaxialReal, TheWholeSpecimenDrivenByItsClampsLeavesTheQuartersResidual) {
  if (!have_the_data()) GTEST_SKIP() << "no " << test::shared_data() / "knit-uniaxial";
  const fs::path quarter = run_example("knit_uniaxial_quarter", "acrylic-garter.toml", "project-template.toml");
  const fs::path full = run_example("knit_uniaxial_full", "acrylic-garter-full.toml", "project-template-full.toml");
  const nlohmann::json q = nlohmann::json::parse(io::read_text(quarter / "out" / "result.json"));
  const nlohmann::json f = nlohmann::json::parse(io::read_text(full / "out" / "result.json"));
  ASSERT_TRUE(f["converged"].get<bool>()) << f["termination"];
  for (const auto& [name, fit] : q["fit"].items()) {
    const double rq = fit["points_rms_mm"].get<double>(), rf = f["fit"][name]["points_rms_mm"].get<double>();
    EXPECT_NEAR(rf / rq, 1.0, 0.03) << name << ": quarter " << rq << " mm, full " << rf << " mm";
    EXPECT_NEAR(f["fit"][name]["force_rms_N"].get<double>(), fit["force_rms_N"].get<double>(),
                0.02 * fit["force_rms_N"].get<double>())
        << name;
  }
}

}  // namespace
}  // namespace tricot
