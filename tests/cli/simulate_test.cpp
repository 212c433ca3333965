// `tricot simulate` from outside (docs/design.md contract): the small examples, the files it writes, and one
// clear error line with the documented exit code for each kind of bad input.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "testing/cli.hpp"
#include "testing/meshio.hpp"
#include "tricot/fem/corotational.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/io/files.hpp"

namespace tricot {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;

// The law is evaluated directly at F; only round-off separates it from the closed form.
constexpr double kClosedFormTolerance = 1e-6;
// Homogeneous FE states: Newton stops at a relative residual of 1e-10.
constexpr double kHomogeneousTolerance = 1e-8;

fs::path write_case(const std::string& name, const std::string& text) {
  const fs::path dir = test::scratch_dir("simulate_" + name);
  std::ofstream(dir / "case.toml") << text;
  return dir / "case.toml";
}

std::string example(const std::string& name) { return (test::source_dir() / "examples" / name / "case.toml").string(); }

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// A small homogeneous neo-Hookean strip: the base of the bad-input cases below.
const std::string kStrip = R"(
[mesh]
width = 10.0
height = 20.0
nx = 2
ny = 2
[law]
type = "neo_hookean"
[[test]]
name = "strip"
kind = "homogeneous"
load_max = 2.0
steps = 4
)";

// --- what it writes ---------------------------------------------------------------------------------

TEST(Simulate, SimpleShearExampleFollowsTheLogRateClosedForm) {
  const fs::path out = test::scratch_dir("simulate_shear_out");
  const auto r = run_tricot("simulate " + example("simple-shear") + " -o " + out.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Table t = io::read_csv(out / "simple-shear" / "steps.csv");
  ASSERT_EQ(t.columns, (std::vector<std::string>{"gamma", "s11", "s22", "s12"}));
  ASSERT_EQ(t.rows.size(), 100u);
  EXPECT_DOUBLE_EQ(t.rows.back()[0], 10.0);
  constexpr double G = 1.0;  // examples/simple-shear/case.toml
  for (const auto& row : t.rows) {
    const auto exact = fem::simple_shear_log_rate(G, row[0]);
    EXPECT_NEAR(row[1], exact.s11, kClosedFormTolerance * std::abs(exact.s11)) << "gamma " << row[0];
    EXPECT_NEAR(row[2], exact.s22, kClosedFormTolerance * std::abs(exact.s22)) << "gamma " << row[0];
    EXPECT_NEAR(row[3], exact.s12, kClosedFormTolerance * std::abs(exact.s12)) << "gamma " << row[0];
  }
  // The shear stress of the log rate passes a maximum and vanishes at large γ.
  EXPECT_LT(t.rows.back()[3], 0.75 * t.rows[30][3]);
  EXPECT_TRUE(fs::exists(out / "simple-shear" / "step_0100.vtu"));
  EXPECT_TRUE(fs::exists(out / "simple-shear" / "closed_form.csv"));
  EXPECT_NE(r.out.find("simple-shear: 100 steps"), std::string::npos) << r.out;
}

TEST(Simulate, HomogeneousUniaxialForceMatchesTheMooneyRivlinClosedForm) {
  // Sliding grip and free side: a uniform uniaxial state, P22 = force per width (docs/theory.md §5).
  const auto file = write_case("mr_homogeneous", R"(
[mesh]
width = 10.0
height = 20.0
element = "Q4"
nx = 2
ny = 3
[law]
type = "mooney_rivlin"
[[test]]
name = "uniform"
kind = "homogeneous"
loads = [2.0, 5.0, 10.0]
)");
  const fs::path out = file.parent_path() / "out";
  const auto r = run_tricot("simulate " + file.string() + " -o " + out.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Table t = io::read_csv(out / "uniform" / "steps.csv");
  ASSERT_EQ(t.columns, (std::vector<std::string>{"step", "load", "edge_displacement", "edge_force", "force_per_width",
                                                 "side_force", "iterations", "cutbacks"}));
  ASSERT_EQ(t.rows.size(), 3u);
  for (const auto& row : t.rows) {
    const double lambda = 1 + row[2] / 10.0;  // quarter height 10 mm
    const double P =
        fem::mooney_rivlin_nominal_stress(fem::paper_mooney_rivlin_terms(), fem::HomogeneousMode::uniaxial, lambda);
    EXPECT_NEAR(row[4], P, kHomogeneousTolerance * P) << "step " << row[0];
    EXPECT_NEAR(row[3], row[4] * 10.0, 1e-12 * row[3]);  // edge force = force per width × full width
  }
  EXPECT_EQ(t.rows[1][1], 5.0);

  if (!test::have_meshio()) GTEST_SKIP() << "python3 lacks meshio: VTU not read back";
  // Cauchy σ_yy = P22 F22 / det F = P22 / λx in every cell (uniform F at every Gauss point).
  const std::string info = test::read_with_meshio(out / "uniform" / "step_0003.vtu", R"(
s = m.cell_data["cauchy_stress"][0]
u = m.point_data["displacement"]
e = m.cell_data["ellipticity"][0]
print(m.cells[0].type, len(m.cells[0].data), repr(float(u[:, 0].min())), repr(float(s[:, 4].min())),
      repr(float(s[:, 4].max())), repr(float(abs(s[:, 0]).max())), repr(float(e.min())), repr(float(e.max())))
)");
  std::istringstream in(info);
  std::string type;
  std::size_t cells = 0;
  double ux_min = 0, syy_min = 0, syy_max = 0, sxx = 0, ell_min = 0, ell_max = 0;
  in >> type >> cells >> ux_min >> syy_min >> syy_max >> sxx >> ell_min >> ell_max;
  // A homogeneous tension of Mooney–Rivlin: strongly elliptic, the same in every cell.
  EXPECT_GT(ell_min, 0) << info;
  EXPECT_NEAR(ell_max, ell_min, 1e-9 * ell_max) << info;
  EXPECT_EQ(type, "quad") << info;
  EXPECT_EQ(cells, 6u) << info;
  const double lambda_x = 1 + ux_min / 5.0;  // the free side moves in: the narrowest point is the side edge
  const double syy = t.rows.back()[4] / lambda_x;
  EXPECT_NEAR(syy_min, syy, kHomogeneousTolerance * syy) << info;
  EXPECT_NEAR(syy_max, syy, kHomogeneousTolerance * syy) << info;
  EXPECT_LT(sxx, kHomogeneousTolerance * syy) << "the free side carries no stress";
}

TEST(Simulate, PrintedDefaultCaseRunsAsIs) {
  const auto printed = run_tricot("simulate --print-config");
  ASSERT_EQ(printed.exit_code, 0);
  EXPECT_NE(printed.out.find("[[test]]"), std::string::npos);
  const auto file = write_case("default", printed.out);
  const fs::path out = file.parent_path() / "out";
  const auto r = run_tricot("simulate " + file.string() + " -o " + out.string() + " -q --no-vtu");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Table t = io::read_csv(out / "uniaxial" / "steps.csv");
  EXPECT_EQ(t.rows.size(), 10u);
  EXPECT_FALSE(fs::exists(out / "uniaxial" / "step_0001.vtu"));
}

TEST(Simulate, OnlyTheChosenTestRuns) {
  const fs::path out = test::scratch_dir("simulate_only");
  const auto r = run_tricot("simulate " + example("biaxial-mooney") + " -o " + out.string() + " --test guide-10 -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "guide-10" / "steps.csv"));
  EXPECT_TRUE(fs::exists(out / "guide-10" / "step_0020.vtu"));
  EXPECT_FALSE(fs::exists(out / "width-held"));
  const io::Table t = io::read_csv(out / "guide-10" / "steps.csv");
  // The guide holds the side: it carries a force, and the grip force rises at every step.
  EXPECT_GT(t.rows.back()[5], 0.0);
  for (std::size_t k = 1; k < t.rows.size(); ++k) EXPECT_GT(t.rows[k][3], t.rows[k - 1][3]);
}

// guide-10 has 20 steps: --vtu-every 6 writes steps 6, 12, 18 and the last, 20; a rerun into the same
// folder removes the step files the new run does not write, so steps.pvd and the folder agree.
TEST(Simulate, VtuEveryWritesTheChosenStepsAndTheLast) {
  const fs::path out = test::scratch_dir("simulate_vtu_every");
  const std::string run = "simulate " + example("biaxial-mooney") + " -o " + out.string() + " --test guide-10 -q";
  ASSERT_EQ(run_tricot(run).exit_code, 0);
  ASSERT_TRUE(fs::exists(out / "guide-10" / "step_0005.vtu"));
  const auto r = run_tricot(run + " --vtu-every 6");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<int> written;
  for (int k = 1; k <= 20; ++k)
    if (fs::exists(out / "guide-10" / fmt::format("step_{:04d}.vtu", k))) written.push_back(k);
  EXPECT_EQ(written, (std::vector<int>{6, 12, 18, 20}));
  std::stringstream pvd;
  pvd << std::ifstream(out / "guide-10" / "steps.pvd").rdbuf();
  EXPECT_NE(pvd.str().find("step_0018.vtu"), std::string::npos) << pvd.str();
  EXPECT_EQ(pvd.str().find("step_0005.vtu"), std::string::npos) << pvd.str();
  EXPECT_EQ(run_tricot(run + " --vtu-every 0").exit_code, 2);
}

TEST(Simulate, ATestsOwnMeshReplacesOnlyTheKeysItSets) {
  const auto file = write_case("own_mesh", kStrip + R"(
[[test]]
name = "coarse"
kind = "homogeneous"
load_max = 2.0
steps = 2
[test.mesh]
element = "Q4"
nx = 1
)");
  const fs::path out = file.parent_path() / "out";
  const auto r = run_tricot("simulate " + file.string() + " -o " + out.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::stringstream strip, coarse;
  strip << std::ifstream(out / "strip" / "step_0001.vtu").rdbuf();
  coarse << std::ifstream(out / "coarse" / "step_0002.vtu").rdbuf();
  // [mesh]: 2 × 2 Q8 = 21 nodes; the override: 1 × 2 Q4 (ny from [mesh]) = 6 nodes.
  EXPECT_NE(strip.str().find("NumberOfPoints=\"21\" NumberOfCells=\"4\""), std::string::npos);
  EXPECT_NE(coarse.str().find("NumberOfPoints=\"6\" NumberOfCells=\"2\""), std::string::npos);
}

TEST(Simulate, HelpShowsACaseFileAndAnExample) {
  const auto r = run_tricot("simulate --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("[[test]]"), std::string::npos);
  EXPECT_NE(r.out.find("tricot simulate examples/"), std::string::npos);
  EXPECT_NE(r.out.find("--no-vtu"), std::string::npos);
}

// --- bad input: one line, the documented exit code ----------------------------------------------------

struct BadInput {
  int exit_code;
  std::string err;
  fs::path out;  ///< the run's output folder
};

BadInput run_bad(const std::string& name, const std::string& text, const std::string& flags = "") {
  const auto file = write_case(name, text);
  const auto r =
      run_tricot("simulate " + file.string() + " -o " + (file.parent_path() / "out").string() + " -q " + flags);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("tricot: error: ", 0), 0u) << r.err;
  return {r.exit_code, r.err, file.parent_path() / "out"};
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(SimulateBadInput, TheBaseCaseIsGood) {
  const auto file = write_case("base", kStrip);
  EXPECT_EQ(run_tricot("simulate " + file.string() + " -o " + (file.parent_path() / "out").string() + " -q").exit_code,
            0);
}

TEST(SimulateBadInput, AMisspelledKeySuggestsTheRightOne) {
  const auto r = run_bad("typo", replace(kStrip, "width = 10.0", "widht = 10.0"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("case.toml:3: mesh.widht: unknown key; did you mean 'width'?"), std::string::npos) << r.err;
}

TEST(SimulateBadInput, ANegativeWidthIsNamed) {
  const auto r = run_bad("negative", replace(kStrip, "width = 10.0", "width = -10.0"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("case.toml:3: mesh.width: out of range (got -10.0"), std::string::npos) << r.err;
}

TEST(SimulateBadInput, AZeroWidthIsNamed) {
  const auto r = run_bad("zero", replace(kStrip, "width = 10.0", "width = 0.0"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("case.toml:3: mesh.width: must be positive (got 0.0, expected > 0)"), std::string::npos)
      << r.err;
}

TEST(SimulateBadInput, ANanIsRejected) {
  const auto r = run_bad("nan", replace(kStrip, "load_max = 2.0", "load_max = nan"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("test[0].load_max: must be a finite number (got nan"), std::string::npos) << r.err;
}

// Issue 29: only force control needs increasing loads; a displacement-controlled grip may hold and
// go back (a lab record's holds and unloading).
TEST(SimulateBadInput, AForceStepListGoingBackwardsNamesTheStep) {
  const auto r =
      run_bad("backwards", replace(kStrip, "load_max = 2.0", "control = \"force\"\nloads = [1.0, 3.0, 2.0]"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("test[0].loads: under force control the loads must increase strictly (step 3 goes backwards)"),
            std::string::npos)
      << r.err;
}

TEST(SimulateBadInput, AForceFirstLoadBelowZeroIsRejected) {
  const auto r =
      run_bad("negative_load", replace(kStrip, "load_max = 2.0", "control = \"force\"\nloads = [-1.0, 1.0]"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("test[0].loads: the first load must be positive (got -1.0"), std::string::npos) << r.err;
}

TEST(SimulateBadInput, AGuidePastTheSymmetryAxisWouldInvertTheMesh) {
  const auto r = run_bad("guide_past", replace(replace(kStrip, "kind = \"homogeneous\"", "kind = \"biaxial\""),
                                               "steps = 4", "steps = 4\nguide = [-6.0]"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("test[0].guide: guide value 1 would pull the side edge past the symmetry axis"),
            std::string::npos)
      << r.err;
}

TEST(SimulateBadInput, AnElementThatInvertsDuringTheRunStopsThatTestWithExitFour) {
  // A clamp (u_x = 0 on the grip) while the guide pulls the side out: the corner element of the
  // (shear-soft) fabric shears until it inverts.
  const std::string text = R"(
[mesh]
width = 110.0
height = 110.0
nx = 4
ny = 4
[law]
type = "reference_fabric"
[solver]
max_cutbacks = 3
[[test]]
name = "corner"
kind = "biaxial"
grip_holds_x = true
guide = [20.0]
load_max = 40.0
steps = 10
)";
  const auto r = run_bad("inverted", text);
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("test 'corner': step "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("inverted"), std::string::npos) << r.err;
}

TEST(SimulateBadInput, AForceTheMaterialCannotCarryFailsAtTheNamedStepAndKeepsTheConvergedOnes) {
  // P(λ) of C10 = 0.1, C20 = −0.01 peaks at 0.218 N/mm (λ ≈ 1.83): 2.18 N on a 10 mm strip.
  const std::string text = R"(
[mesh]
width = 10.0
height = 20.0
element = "Q4"
nx = 1
ny = 2
[law]
type = "mooney_rivlin"
[law.mooney_rivlin]
terms = ["C10", "C20"]
values = [0.1, -0.01]
[solver]
max_cutbacks = 4
[[test]]
name = "soft"
kind = "homogeneous"
control = "force"
loads = [1.0, 2.0, 3.0, 4.0]
)";
  const auto r = run_bad("too_soft", text);
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("test 'soft': step 3 of 4 (load 3)"), std::string::npos) << r.err;
  const io::Table t = io::read_csv(r.out / "soft" / "steps.csv");
  EXPECT_EQ(t.rows.size(), 2u);
}

TEST(SimulateBadInput, AMissingCaseFileExitsThree) {
  const auto r = run_tricot("simulate /nonexistent/case.toml -o /tmp/never -q");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/case.toml: file not found"), std::string::npos) << r.err;
}

TEST(SimulateBadInput, AnUnknownTestNameSuggestsTheClosestOne) {
  const auto r = run_bad("unknown_test", kStrip, "--test strp");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--test: no test of that name; did you mean 'strip'?"), std::string::npos) << r.err;
}

TEST(SimulateBadInput, AKindAndASideThatDisagreeAreNamed) {
  const auto r = run_bad("kind_side", replace(replace(kStrip, "kind = \"homogeneous\"", "kind = \"uniaxial\""),
                                              "steps = 4", "steps = 4\nside = \"guide\""));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("test[0].side: a uniaxial test has a free side edge"), std::string::npos) << r.err;
}

TEST(SimulateBadInput, TwoTestsWithOneNameAreRejected) {
  const auto r = run_bad("twins", kStrip + "[[test]]\nname = \"strip\"\n");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("test[1].name: two tests have this name"), std::string::npos) << r.err;
}

TEST(SimulateBadInput, MooneyRivlinValuesMustMatchTheTerms) {
  const auto r =
      run_bad("mr_values",
              replace(kStrip, "type = \"neo_hookean\"",
                      "type = \"mooney_rivlin\"\n[law.mooney_rivlin]\nterms = [\"C10\", \"C01\"]\nvalues = [0.1]"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("law.mooney_rivlin.values: one value per term (got 1 values, expected 2 as in terms)"),
            std::string::npos)
      << r.err;
}

// A stalled Newton names where its residual sits. The reference knit with wrinkling in the §4 rig
// (docs/validation.md §9): setting the 40 % transverse dimension, the line search stops at the rig's
// corner, the free side between the guide's end and the clips (X = 55 mm, Y = 53.1 mm of the quarter).
// A Newton that runs out of iterations says where its residual sits: the node whose free dofs carry
// the largest part (here the rig's first setting increment from rest, which takes 7 iterations, given 2
// and no cutback).
TEST(Simulate, ANewtonThatDoesNotConvergeNamesTheNodeWhereItsResidualSits) {
  const auto file = write_case("stalled", R"(
[mesh]
element = "Q8"
nx = 12
ny = 10
[law]
type = "reference_fabric"
[solver]
max_iterations = 2
max_cutbacks = 0
[[test]]
name = "s110-wale-040"
kind = "rig"
side = 110.0
pull = "wale"
transverse_strain = 0.4
pull_strain = 0.65
steps = 21
)");
  const auto r =
      run_tricot("simulate " + file.string() + " -o " + (file.parent_path() / "out").string() + " -q --no-vtu");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("after 2 Newton iterations"), std::string::npos) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      r.err, m, std::regex(R"(largest [0-9.e+-]+ N at node [0-9]+, X = \(([0-9.e+-]+), ([0-9.e+-]+)\) mm\))")))
      << r.err;
  for (int k = 1; k <= 2; ++k) {  // a node of the 55 × 55 mm quarter
    EXPECT_GE(std::stod(m[k]), 0.0) << r.err;
    EXPECT_LE(std::stod(m[k]), 55.0) << r.err;
  }
}

}  // namespace
}  // namespace tricot
