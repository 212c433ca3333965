// tricot relax LOG -o DIR (apps/tricot/relax.cpp, src/project/pipeline/relax.cpp): a relaxation test's LabVIEW log
// (tab, decimal comma, 10 header lines) with a known Prony series, fitted through the command line.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "testing/cli.hpp"
#include "testing/experiment_case.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"
#include "tricot/synth/lab_record.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;
using test::scratch_dir;

// The requirement: τ = 360 s within 2 % from a noisy record (σ 0.1 N on 10 N of relaxation).
constexpr double kTauTolerance = 0.02;
// The viscous excess of the chosen fit against the truth's closed form at T = 600 s: τ and F_i within a
// few % make the excess within a few % of itself.
constexpr double kExcessTolerance = 0.05;

struct Relaxed {
  test::CliRun cli;
  nlohmann::json result;
  fs::path out;
};

Relaxed relax(const std::string& name, const synth::RelaxationRecordOptions& o, const std::string& flags) {
  const fs::path dir = scratch_dir(name);
  io::write_atomic(dir / "relaxation.txt", io::to_log_text(synth::labview_log(synth::make_relaxation_record(o))));
  Relaxed r;
  r.out = dir / "out";
  r.cli = run_tricot("relax " + (dir / "relaxation.txt").string() + " --time Temps --force Force -o " + r.out.string() +
                     " " + flags);
  if (r.cli.exit_code == 0) r.result = nlohmann::json::parse(io::read_text(r.out / "relax.json"));
  return r;
}

TEST(Relax, RecoversTau360sWithin2PercentAndJudgesATestQuasiStatic) {
  synth::RelaxationRecordOptions o;  // τ = 360 s, F1 = 10 N, F∞ = 20 N, 1 h hold at 2 Hz, σ 0.1 N
  const Relaxed r = relax("relax_one", o, "--crosshead Traverse --duration 600");
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.err;
  ASSERT_EQ(r.result["chosen_terms"], 1) << r.cli.out;
  const auto& fit = r.result["fits"][0];
  EXPECT_NEAR(fit["terms"][0]["tau_s"].get<double>() / 360.0, 1.0, kTauTolerance) << r.cli.out;
  // Truth: excess(T) = (F1/F∞)(τ/T)(1 − exp(−T/τ)) = 0.5 · 0.6 · (1 − e^(−5/3)) = 0.2433: not quasi-static at 5 %.
  const double truth = 0.5 * 360.0 / 600.0 * (1 - std::exp(-600.0 / 360.0));
  EXPECT_NEAR(r.result["quasi_static"]["viscous_excess"].get<double>() / truth, 1.0, kExcessTolerance);
  EXPECT_FALSE(r.result["quasi_static"]["quasi_static"].get<bool>());
  EXPECT_TRUE(fs::exists(r.out / "relax.csv"));
}

TEST(Relax, TellsATwoTermRecordFromAOneTermOne) {
  synth::RelaxationRecordOptions o;
  o.tau_s = {30, 360};
  o.amplitudes_N = {8, 10};
  const Relaxed r = relax("relax_two", o, "--crosshead Traverse");
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.err;
  EXPECT_EQ(r.result["chosen_terms"], 2) << r.cli.out;
  EXPECT_NEAR(r.result["fits"][1]["terms"][1]["tau_s"].get<double>() / 360.0, 1.0, 0.05) << r.cli.out;
}

TEST(Relax, AnUnknownColumnGetsADidYouMean) {
  const Relaxed r = relax("relax_column", {}, "--crosshead Travers");
  EXPECT_EQ(r.cli.exit_code, 2);
  EXPECT_NE(r.cli.err.find("did you mean"), std::string::npos) << r.cli.err;
}

}  // namespace
}  // namespace tricot::project
