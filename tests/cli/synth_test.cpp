// tricot synth EXPERIMENT.toml -o DIR (apps/tricot/synth.cpp, src/project/pipeline/synthesis.cpp): the
// experiment it writes.
#include <gtest/gtest.h>

#include <cmath>

#include "testing/experiment_case.hpp"
#include "tricot/project/experiment_files.hpp"
#include "testing/cli.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;
using test::scratch_dir;
using test::small_experiment;
using test::write_file;

// Force control: the FE's grip force matches the prescribed load to the Newton tolerance (1e-10 of
// the reaction) and the rounding of a 17-digit CSV.
constexpr double kForceMatchesLoad = 1e-8;

fs::path synth(const std::string& name, const std::string& synth_table = "nx = 3\nny = 5\n") {
  const fs::path dir = scratch_dir(name);
  write_file(dir / "experiment.toml", small_experiment(synth_table));
  const auto r = run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string() + " -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir / "exp";
}

TEST(Synth, WritesTheGripResponseOfEveryStep) {
  const fs::path exp = synth("synth_writes");
  const io::Table f = io::read_csv(exp / "tension" / kForcesFile);
  EXPECT_EQ(f.columns, (std::vector<std::string>{"step", "load", "edge_displacement", "edge_force"}));
  ASSERT_EQ(f.rows.size(), 10u);
  for (std::size_t k = 0; k < f.rows.size(); ++k) {
    EXPECT_EQ(f.rows[k][0], double(k + 1));
    EXPECT_NEAR(f.rows[k][1], 0.5 * double(k + 1), 1e-12);
    EXPECT_NEAR(f.rows[k][3] / f.rows[k][1], 1.0, kForceMatchesLoad);
    if (k > 0) {
      EXPECT_GT(f.rows[k][2], f.rows[k - 1][2]);  // the strip lengthens under a growing force
    }
  }
}

TEST(Synth, WritesTheFieldOfEveryPointAtEveryStep) {
  const fs::path exp = synth("synth_field");
  const ident::TestData d = read_test_data(exp, "tension", ident::FieldKind::cumulative);
  ASSERT_EQ(d.point_count(), 15);  // 3 × 5
  ASSERT_EQ(d.steps(), 10);
  // Grid 1 mm inside the quarter 10 × 30 mm.
  EXPECT_DOUBLE_EQ(d.points(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(d.points(1, 0), 1.0);
  EXPECT_DOUBLE_EQ(d.points(0, 14), 9.0);
  EXPECT_DOUBLE_EQ(d.points(1, 14), 29.0);
  for (int k = 0; k < d.steps(); ++k)
    for (int p = 0; p < d.point_count(); ++p) {
      // Tension along y: every material point moves up, less than the grip; the strip narrows.
      EXPECT_GT(d.v(k, p), 0);
      EXPECT_LT(d.v(k, p), d.edge_displacement[k]);
      EXPECT_LE(d.u(k, p), 0);
      if (p >= 3) {
        EXPECT_GT(d.v(k, p), d.v(k, p - 3));  // higher up, further up
      }
    }
}

TEST(Synth, WritesTheTruth) {
  const fs::path exp = synth("synth_truth");
  const auto t = read_truth(exp);
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->law, "mooney_rivlin");
  EXPECT_EQ(t->names, (std::vector<std::string>{"C10", "C20", "C21", "C03"}));
  EXPECT_EQ(t->values, (std::vector<double>{0.1, -0.025, 0.015, 0.01}));
  ASSERT_EQ(t->tests.size(), 1u);
  EXPECT_EQ(t->tests[0].control, "force");
  EXPECT_EQ(t->tests[0].mesh.nx, 3);
  EXPECT_EQ(t->tests[0].mesh.ny, 8);
  EXPECT_EQ(t->tests[0].points, 15);
  EXPECT_EQ(t->tests[0].sigma.field, 0);
}

TEST(Synth, NoiseIsReproducibleAndOfTheRequestedSize) {
  const fs::path clean = synth("synth_clean", "nx = 6\nny = 10\n");
  const fs::path a = synth("synth_noise_a", "nx = 6\nny = 10\nnoise_relative = 0.01\n");
  const fs::path b = synth("synth_noise_b", "nx = 6\nny = 10\nnoise_relative = 0.01\n");
  EXPECT_EQ(io::read_text(a / "tension" / kFieldFile), io::read_text(b / "tension" / kFieldFile));
  const ident::TestData c = read_test_data(clean, "tension", ident::FieldKind::cumulative);
  const ident::TestData n = read_test_data(a, "tension", ident::FieldKind::cumulative);
  const auto t = read_truth(a);
  ASSERT_TRUE(t.has_value());
  const double sigma = t->tests[0].sigma.field;
  const double rms = std::sqrt((c.u.squaredNorm() + c.v.squaredNorm()) / double(2 * c.u.size()));
  EXPECT_NEAR(sigma, 0.01 * rms, 1e-12 * rms);
  const double spread = std::sqrt(((n.u - c.u).squaredNorm() + (n.v - c.v).squaredNorm()) / double(2 * c.u.size()));
  // 1200 samples: the sample σ is within 10 % of the true one with overwhelming probability.
  EXPECT_NEAR(spread / sigma, 1.0, 0.1);
}

TEST(Synth, IncrementalPointsThatLeaveTheStripAreLeftOut) {
  const fs::path exp = synth("synth_incremental", "nx = 3\nny = 5\ninset = 0.5\nfield_kind = \"incremental\"\n");
  const auto t = read_truth(exp);
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->field_kind, ident::FieldKind::incremental);
  // The strip narrows from 10 mm (quarter) to ~8 mm: the points at x = 9.5 mm leave it.
  EXPECT_GT(t->tests[0].dropped_points, 0);
  const ident::TestData d = read_test_data(exp, "tension", ident::FieldKind::incremental);
  EXPECT_EQ(d.point_count() + t->tests[0].dropped_points, 15);
  for (int p = 0; p < d.point_count(); ++p) EXPECT_LT(d.points(0, p), 9.5);
}

TEST(Synth, RejectsAbsoluteAndRelativeNoiseTogether) {
  const fs::path dir = scratch_dir("synth_both_noises");
  write_file(dir / "experiment.toml", small_experiment("noise_relative = 0.01\nnoise_field = 0.001\n"));
  const auto r = run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("synth.noise_field: give either absolute σ or noise_relative"), std::string::npos) << r.err;
}

TEST(Synth, PrintConfigReadsBack) {
  const fs::path dir = scratch_dir("synth_print_config");
  const auto p = run_tricot("synth --print-config");
  ASSERT_EQ(p.exit_code, 0);
  EXPECT_NE(p.out.find("[synth]"), std::string::npos);
  write_file(dir / "default.toml", p.out);
  const auto r = run_tricot("synth " + (dir / "default.toml").string() + " -o " + (dir / "exp").string() + " -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "exp" / kTruthFile));
}

}  // namespace
}  // namespace tricot::project
