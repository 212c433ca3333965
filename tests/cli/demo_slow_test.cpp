// tricot demo --table1 end to end (about a minute): the paper's Table 1 reproduced, noise-free.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "testing/cli.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/log.hpp"

#include <nlohmann/json.hpp>

namespace tricot {
namespace {

namespace fs = std::filesystem;

// Issue 4's acceptance for the both-data run: data generated on a finer mesh leave a discretisation
// bias, C03 (the weakest coefficient) the largest.
constexpr double kStrongCoefficients = 1e-3;  // C10, C20, C21 within 0.1 %
constexpr double kC03 = 1e-2;                 // C03 within 1 %

TEST(Demo, ReproducesTableOneFromNoiseFreeData) {
  const fs::path dir = test::scratch_dir("demo");
  const auto r = test::run_tricot("demo --table1 -q -o " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Table 1"), std::string::npos);
  for (const char* f : {"table1.md", "table1.csv", "epsilon.csv", "plots/epsilon.png", "both/result.json",
                        "edge/result.json", "field/result.json", "both/plots/history.png", "experiment/truth.json"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;

  // table1.csv: data,coefficient,target,identified,relative_error,...,termination
  std::istringstream in(io::read_text(dir / "out" / "table1.csv"));
  std::string line;
  std::getline(in, line);
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) c.push_back(cell);
    ASSERT_EQ(c.size(), 13u) << line;
    EXPECT_NE(c[12], "max_iterations") << line;
    ++rows;
    if (c[0] != "both") continue;
    const double e = std::abs(std::stod(c[4]));
    EXPECT_LT(e, c[1] == "C03" ? kC03 : kStrongCoefficients) << line;
  }
  EXPECT_EQ(rows, 12);
}

// The chain (issue 13) in its reduced form: a rig test's setting in images of its own, the hold, then
// the pull; the synchronisation on the pull recovers the lab record's clock offset and every pull
// image's force, and the experiment's steps are the pull's only.
constexpr double kOffsetTolerance = 0.005;  // s: issue 11's cross-head sync reached 1.2 ms on a uniaxial strip
constexpr double kForceSigmas = 5;          // each image's force within 5 σ of the log's noise

TEST(Demo, TheSmallChainRecoversTheClockOffsetAndTheForcesOfTheRigTests) {
  const fs::path dir = test::scratch_dir("demo_small");
  const auto r = test::run_tricot("demo --small -q -o " + (dir / "out").string());
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 4) << r.err;  // two LM iterations need not converge
  const fs::path out = dir / "out";
  const auto sync = nlohmann::json::parse(io::read_text(out / "experiment" / "sync.json"));
  for (const char* name : {"s110-wale-040", "s110-course-030"}) {
    SCOPED_TRACE(name);
    const auto truth = nlohmann::json::parse(io::read_text(out / "raw" / name / "lab" / "truth.json"));
    const auto& s = sync.at(name);
    EXPECT_EQ(s.at("method"), "crosshead");
    EXPECT_NEAR(s.at("clock_offset_s").get<double>(), truth.at("clock_offset_s").get<double>(), kOffsetTolerance);
    EXPECT_NEAR(s.at("tare_N").get<double>(), truth.at("tare_N").get<double>(), 0.02);
    const int first = 1 + truth.at("setting_frames").get<int>() + truth.at("hold_frames").get<int>();
    EXPECT_EQ(truth.at("setting_frames").get<int>(), 2);
    EXPECT_EQ(s.at("first_step_image").get<int>(), first);
    const io::LogTable f = io::read_log(out / "experiment" / name / "forces.csv", io::LogFormat{',', false, 1});
    const auto force = f.numbers("edge_force");
    ASSERT_EQ(force.size(), 6u);  // the pull's steps only
    const double sigma = truth.at("force_noise_N").get<double>();
    for (std::size_t k = 0; k < force.size(); ++k)
      EXPECT_NEAR(force[k], truth.at("force_N")[std::size_t(first) + k].get<double>(), kForceSigmas * sigma) << k;
  }
  const auto stages = nlohmann::json::parse(io::read_text(out / "stages.json"));
  ASSERT_EQ(stages.at("stages").size(), 5u);
  EXPECT_TRUE(fs::exists(out / "identify" / "report.html"));
  EXPECT_NE(r.out.find("report: "), std::string::npos) << r.out;
}

}  // namespace
}  // namespace tricot
