// The whole experimental branch on rendered images (issue 11, examples/lab-uniaxial): `tricot synth`
// renders a uniaxial Mooney–Rivlin strip and writes its lab record (LabVIEW load-cell log with a clock
// offset, tare and noise; camera log) → `tricot dic` tracks the images → `tricot experiment` synchronises
// the load cell and folds the field into the quarter model, with the DIC's σ → `tricot identify` finds
// C10, C20, C21 (C03 held at its truth) from the load cell's force and the field, with the DIC's σ,
// cumulative and incremental (about 15 s in all).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "testing/cli.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;
using test::scratch_dir;

// The requirements.
constexpr double kRelativeTolerance = 0.01;  // C10, C20, C21 within 1 % of the truth
constexpr double kStdErrors = 3;             // the truth within 3 standard errors, σ from the DIC
constexpr double kOffsetToleranceS = 0.010;
const std::vector<std::pair<std::string, double>> kTruth = {{"C10", 0.1}, {"C20", -0.025}, {"C21", 0.015}};

struct Chain {
  fs::path dir;
};

// synth and dic once: both field kinds read the same DIC run (it writes increments.csv too).
const Chain& raw() {
  static const Chain c = [] {
    Chain c{scratch_dir("experiment_chain")};
    const fs::path ex = test::source_dir() / "examples" / "lab-uniaxial";
    for (const char* f : {"experiment.toml", "dic.toml", "lab.toml", "project-template.toml"})
      fs::copy_file(ex / f, c.dir / f, fs::copy_options::overwrite_existing);
    auto r = run_tricot("synth " + (c.dir / "experiment.toml").string() + " -o " + (c.dir / "raw").string() + " -q");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::string images;
    for (int k = 0; k <= 20; ++k)
      images += " " + (c.dir / "raw" / "tension" / "images" / fmt::format("frame_{:04d}.png", k)).string();
    r = run_tricot("dic " + (c.dir / "dic.toml").string() + images + " -o " + (c.dir / "raw" / "dic").string() + " -q");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return c;
  }();
  return c;
}

void identify_and_check(const std::string& field_kind) {
  const Chain& c = raw();
  std::string lab = io::read_text(c.dir / "lab.toml");
  lab.replace(lab.find("field_kind = \"cumulative\""), 25, "field_kind = \"" + field_kind + "\"");
  io::write_atomic(c.dir / ("lab-" + field_kind + ".toml"), lab);
  const fs::path exp = c.dir / ("experiment-" + field_kind), out = c.dir / ("identify-" + field_kind);
  auto r =
      run_tricot("experiment " + (c.dir / ("lab-" + field_kind + ".toml")).string() + " -o " + exp.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::printf("%s", r.out.c_str());
  const auto sync = nlohmann::json::parse(io::read_text(exp / "sync.json"));
  EXPECT_NEAR(sync["tension"]["clock_offset_s"].get<double>(), 0.37, kOffsetToleranceS);
  r = run_tricot("identify " + (exp / "project.toml").string() + " -o " + out.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = nlohmann::json::parse(io::read_text(out / "result.json"));
  EXPECT_EQ(j["covariance_from"], "measurement_sigma");
  for (const auto& [name, truth] : kTruth) {
    const double value = j["parameters"][name].get<double>(), se = j["std_error"][name].get<double>();
    std::printf("%s %s = %.6g (truth %.6g, %+.3f %%), std error %.3g: %.2f SE\n", field_kind.c_str(), name.c_str(),
                value, truth, 100 * (value / truth - 1), se, std::abs(value - truth) / se);
    EXPECT_NEAR(value / truth, 1.0, kRelativeTolerance) << name;
    EXPECT_LE(std::abs(value - truth), kStdErrors * se) << name;
  }
}

// One test for both field kinds: they read the same synth and DIC run (~20 s).
TEST(ExperimentChain, ImagesThroughDicExperimentAndIdentifyRecoverTheLawWithCumulativeAndIncrementalFields) {
  identify_and_check("cumulative");
  identify_and_check("incremental");
}

}  // namespace
}  // namespace tricot::project
