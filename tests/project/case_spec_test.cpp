// project/case_spec.cpp: the typed case spec (mesh, law, solver, rig, tests), its defaults and the
// engine values it builds, each error once, at its key's file and line.
#include "tricot/project/case_spec.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <memory>

#include "testing/paths.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/fem/wrinkling.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

// Exact: the same double arithmetic on both sides (the rig's grip and guide displacements).
constexpr double kExact = 0;

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

const char* const kRigCase = R"(
[mesh]
nx = 4
ny = 3
grading_x = 0.5

[law]
type = "reference_fabric"

[law.reference_fabric]
k_P = 0.08

[rig]
guide_gap = 0.2
setting_steps = 3

[[test]]
name = "course-030"
kind = "rig"
side = 150.0
pull = "course"
transverse_strain = 0.3
pull_strain = 1.0
steps = 5
)";

TEST(CaseSpec, TheSchemasDefaultsAreTheSpecsDefaults) {
  io::Node root = io::default_config(case_schema());
  const CaseSpec read = CaseSpec::from_config(root);
  const CaseSpec code;
  EXPECT_EQ(read.mesh.width, code.mesh.width);
  EXPECT_EQ(read.mesh.nx, code.mesh.nx);
  EXPECT_EQ(read.mesh.grading_x, code.mesh.grading_x);
  EXPECT_EQ(read.solver.tolerance, code.solver.tolerance);
  EXPECT_EQ(read.solver.max_cutbacks, code.solver.max_cutbacks);
  EXPECT_EQ(read.rig.guide_gap, code.rig.guide_gap);
  EXPECT_EQ(read.rig.setting_steps, code.rig.setting_steps);
  EXPECT_EQ(read.rig.clips_follow_guide, code.rig.clips_follow_guide);
  EXPECT_EQ(read.law.type, code.law.type);
  EXPECT_EQ(read.law.mooney_rivlin.values, code.law.mooney_rivlin.values);
  EXPECT_EQ(read.law.reference_fabric.k_P, code.law.reference_fabric.k_P);
  EXPECT_EQ(read.law.reference_fabric.s_J, code.law.reference_fabric.s_J);
  EXPECT_EQ(read.law.response_surface.shear_stiffness, code.law.response_surface.shear_stiffness);
}

TEST(CaseSpec, ARigTestFromAFileIsTheEnginesRigTest) {
  const io::Node root = io::parse_config(case_schema(), kRigCase, "case.toml");
  const CaseSpec spec = CaseSpec::from_config(root);
  const fem::TestModel t = spec.test.at(0).model(spec.mesh, spec.rig);
  // The quarter is 75 mm; the grip reaches H(√(1 + 2ε) − 1) in 5 steps; the guide W(√(1 + 2εt) − 1).
  ASSERT_EQ(t.loads.size(), 5u);
  EXPECT_NEAR(t.loads.back(), 75 * (std::sqrt(3.0) - 1), 1e-12);
  ASSERT_EQ(t.guide.size(), 1u);
  EXPECT_NEAR(t.guide[0], 75 * (std::sqrt(1.6) - 1), 1e-12);
  EXPECT_EQ(t.material_angle, 90);
  EXPECT_NEAR(t.guide_gap, 0.2 * 75, 1e-12);
  EXPECT_EQ(t.guide_setting_steps, 3);
  // (4 × 3 Q8: (2·4 + 1)(2·3 + 1) − 4·3 nodes.)
  EXPECT_EQ(t.mesh.nodes(), 9 * 7 - 12);

  fem::RigOptions o;
  o.name = "course-030", o.side = 150, o.pull = fem::PullDirection::course;
  o.transverse_strain = 0.3, o.pull_strain = 1.0, o.steps = 5;
  o.nx = 4, o.ny = 3, o.grading_y = 1, o.grading_x = 0.5, o.guide_gap = 0.2, o.setting_steps = 3;
  const fem::TestModel engine = fem::make_rig_test(o);
  EXPECT_NEAR((engine.mesh.X - t.mesh.X).cwiseAbs().maxCoeff(), 0, kExact);
  EXPECT_EQ(engine.loads, t.loads);
  EXPECT_EQ(spec.test[0].mesh_options(spec.mesh).width, 75);
}

// The paper's rig written as data (examples/rig-as-data: a .geo quarter, ties, a tapered guide end and a
// pantograph clamp as [[test.boundary]] tables) gives the built-in rig's answer: the same nodes, the same
// forces and displacements at every setting increment and pull step, to 1e-10.
TEST(CaseSpec, TheRigWrittenAsDataGivesTheBuiltInRigsAnswerTo1e10) {
  auto run = [](const char* file, fem::TestModel& model) {
    const std::filesystem::path path = test::source_dir() / "examples/rig-as-data" / file;
    const CaseSpec spec = CaseSpec::from_config(io::parse_config(case_schema(), io::read_text(path), path.string()));
    model = spec.test.at(0).model(spec.mesh, spec.rig);
    const fem::SimulationResult r = fem::simulate(model, *spec.law.law(), spec.solver.options());
    EXPECT_EQ(r.termination, fem::SolveTermination::converged) << r.message;
    return r;
  };
  fem::TestModel builtin, data;
  const fem::SimulationResult a = run("builtin.toml", builtin), b = run("case.toml", data);
  ASSERT_EQ(builtin.mesh.nodes(), data.mesh.nodes());
  ASSERT_EQ(a.setting.size(), 4u);
  ASSERT_EQ(a.steps.size(), 21u);
  ASSERT_EQ(b.steps.size(), 25u);
  // Each node of the .geo's mesh is a node of the built-in's.
  std::vector<int> same(data.mesh.nodes(), -1);
  for (int n = 0; n < data.mesh.nodes(); ++n)
    for (int m = 0; m < builtin.mesh.nodes(); ++m)
      if ((data.mesh.X.col(n) - builtin.mesh.X.col(m)).norm() < 1e-10 * 55) same[n] = m;
  ASSERT_EQ(std::count(same.begin(), same.end(), -1), 0);
  double u_max = 0, du = 0, F_max = 0, dF = 0;
  auto compare = [&](const fem::StepResult& x, const fem::StepResult& y) {
    for (int n = 0; n < data.mesh.nodes(); ++n) {
      u_max = std::max(u_max, x.u.segment<2>(2 * same[n]).norm());
      du = std::max(du, (x.u.segment<2>(2 * same[n]) - y.u.segment<2>(2 * n)).norm());
    }
    const double side = 2 * y.resultants.at(1)(0);  // the guide's pull: resultants top, right, left, bottom
    F_max = std::max({F_max, std::abs(x.edge_force), std::abs(x.side_force)});
    dF = std::max({dF, std::abs(x.edge_force - y.edge_force), std::abs(x.side_force - side)});
  };
  for (size_t i = 0; i < 4; ++i) compare(a.setting[i], b.steps[i]);
  for (size_t k = 0; k < 21; ++k) compare(a.steps[k], b.steps[4 + k]);
  EXPECT_GT(u_max, 10);  // the guide opens by 18.8 mm, the grip pulls 28.4 mm
  EXPECT_GT(F_max, 10);
  EXPECT_LT(du / u_max, 1e-10) << du;
  EXPECT_LT(dF / F_max, 1e-10) << dF;
  std::cerr << "rig as data: |du| / max |u| = " << du / u_max << ", |dF| / max |F| = " << dF / F_max << "\n";
}

TEST(CaseSpec, ARigTestBuiltInCodeIsTheSameAsFromAFile) {
  const io::Node root = io::parse_config(case_schema(), kRigCase, "case.toml");
  const CaseSpec file = CaseSpec::from_config(root);
  CaseSpec code;
  code.mesh.nx = 4, code.mesh.ny = 3, code.mesh.grading_x = 0.5;
  code.rig.guide_gap = 0.2, code.rig.setting_steps = 3;
  TestSpec t;
  t.name = "course-030", t.kind = "rig", t.side = 150.0, t.pull = "course";
  t.transverse_strain = 0.3, t.pull_strain = 1.0, t.steps = 5;
  code.test.push_back(t);
  const fem::TestModel a = file.models().at(0), b = code.models().at(0);
  EXPECT_EQ(a.loads, b.loads);
  EXPECT_EQ(a.guide, b.guide);
  EXPECT_NEAR((a.mesh.X - b.mesh.X).cwiseAbs().maxCoeff(), 0, kExact);
}

TEST(CaseSpec, TheReferenceFabricsShrinkageAndJammingAreRead) {
  const io::Node root = io::parse_config(case_schema(), kRigCase, "case.toml");
  const auto law = CaseSpec::from_config(root).law.law();
  const auto names = law->coefficient_names();
  const auto c = law->coefficients();
  const auto k_P = std::find(names.begin(), names.end(), "k_P");
  ASSERT_NE(k_P, names.end());
  EXPECT_EQ(c(k_P - names.begin()), 0.08);
}

TEST(CaseSpec, ABadRigValueNamesItsKeyAndLine) {
  const std::string text = std::string(kRigCase) + "\n";
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = text;
    s.replace(s.find(from), from.size(), to);
    const io::Node root = io::parse_config(case_schema(), s, "case.toml");
    const CaseSpec spec = CaseSpec::from_config(root);
    return message_of([&] { spec.models(); });
  };
  EXPECT_EQ(with("guide_gap = 0.2", "guide_gap = 0.6"),
            "case.toml:14: rig.guide_gap: test 'course-030': out of range (got 0.6, expected [0, 0.5))");
  EXPECT_EQ(with("pull_strain = 1.0", "pull_strain = 0.0"),
            "case.toml:23: test[0].pull_strain: test 'course-030': out of range (got 0, expected > 0)");
  EXPECT_EQ(with("side = 150.0", "side = \"guide\""),
            "case.toml:20: test[0].side: a rig test's side is the specimen side in mm (got \"guide\", expected a "
            "number > 0)");
}

TEST(CaseSpec, ANumberSideIsOnlyForARig) {
  const io::Node root =
      io::parse_config(case_schema(), "[[test]]\nname = \"a\"\nkind = \"biaxial\"\nside = 110\n", "case.toml");
  const CaseSpec spec = CaseSpec::from_config(root);
  EXPECT_EQ(message_of([&] { spec.models(); }),
            "case.toml:4: test[0].side: a number is the specimen side of a rig test (got 110.0, expected free or "
            "guide, or kind = \"rig\")");
}

TEST(CaseSpec, AnUnstableReferenceFabricNamesItsCoefficient) {
  const io::Node root = io::parse_config(
      case_schema(), "[law]\ntype = \"reference_fabric\"\n[law.reference_fabric]\nk_P = 0.5\n", "case.toml");
  EXPECT_EQ(message_of([&] { CaseSpec::from_config(root).law.law(); }),
            "case.toml:4: law.reference_fabric.k_P: out of range (got 0.500000, expected k_P^2 < k_C k_W (a stable "
            "knit at rest))");
}

// The laws' own checks name the keys of their [law.*] table (no renaming on the way, issue 10).
TEST(CaseSpec, AMooneyRivlinErrorNamesTheKeyOfItsTable) {
  const io::Node root = io::parse_config(
      case_schema(), "[law.mooney_rivlin]\nterms = [\"C10\", \"C10\"]\nvalues = [0.1, 0.2]\n", "case.toml");
  EXPECT_EQ(message_of([&] { CaseSpec::from_config(root).law.law(); }),
            "case.toml:2: law.mooney_rivlin.terms: coefficient given twice (got C10, expected each C<i><j> once)");
  LawSpec code;
  code.mooney_rivlin.values[1] = std::nan("");
  EXPECT_EQ(message_of([&] { code.law(); }).rfind("law.mooney_rivlin.values: C20 is not a finite number", 0), 0u)
      << message_of([&] { code.law(); });
}

TEST(CaseSpec, AResponseSurfaceErrorNamesTheKeyOfItsTable) {
  const io::Node root = io::parse_config(case_schema(),
                                         "[law]\ntype = \"response_surface\"\n[law.response_surface]\n"
                                         "preset = \"general\"\ncourse = [\"C1\", \"C1\"]\n",
                                         "case.toml");
  EXPECT_EQ(message_of([&] { CaseSpec::from_config(root).law.law(); }),
            "case.toml:5: law.response_surface.course: repeated monomial (got course monomial (1, 0), expected each "
            "(p, q) once per force)");
  LawSpec code;
  code.type = "response_surface";
  code.response_surface.shear_stiffness = 0;
  EXPECT_EQ(message_of([&] { code.law(); }),
            "law.response_surface.shear_stiffness: out of range (got 0.000000, expected > 0 N/mm)");
}

// `[law] wrinkling` wraps the law of `type` in a tension-field membrane (issue 30); off by default.
TEST(CaseSpec, WrinklingWrapsTheLawInATensionFieldMembrane) {
  const io::Node plain = io::parse_config(case_schema(), "[law]\ntype = \"reference_fabric\"\n", "case.toml");
  EXPECT_EQ(dynamic_cast<const fem::WrinklingLaw*>(CaseSpec::from_config(plain).law.law().get()), nullptr);
  const io::Node root = io::parse_config(
      case_schema(), "[law]\ntype = \"reference_fabric\"\nwrinkling = true\nresidual_stiffness = 0.01\n", "case.toml");
  const std::unique_ptr<fem::Law> law = CaseSpec::from_config(root).law.law();
  const auto* w = dynamic_cast<const fem::WrinklingLaw*>(law.get());
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->options().residual_stiffness, 0.01);
  EXPECT_EQ(w->name(), "reference_fabric");
  EXPECT_NE(dynamic_cast<const fem::ReferenceFabric*>(&w->inner()), nullptr);
  LawSpec code;
  code.wrinkling = true;
  code.wrinkling_options.residual_stiffness = 0.5;
  EXPECT_EQ(message_of([&] { code.law(); }), "law.residual_stiffness: out of range (got 0.5, expected [0, 0.5))");
}

// A law names its keys relative to its law table (`law.neo_hookean.mu`, `law.residual_stiffness`): a
// [[law.region]]'s error is placed at the region's own table and line.
TEST(CaseSpec, ARegionLawsErrorIsPlacedAtItsOwnTable) {
  auto message = [](const std::string& region, const std::string& mu) {
    const std::string text =
        "[law]\ntype = \"neo_hookean\"\n[[law.region]]\nname = \"lesion\"\ntype = \"neo_hookean\"\n" + region +
        "[law.region.neo_hookean]\nmu = " + mu + "\n";
    const CaseSpec spec = CaseSpec::from_config(io::parse_config(case_schema(), text, "case.toml"));
    return message_of([&] { spec.law.law({"lesion"}); });
  };
  EXPECT_EQ(message("", "0.0"),
            "case.toml:7: law.region[0].neo_hookean.mu: out of range (got 0.000000, expected > 0 N/mm)");
  EXPECT_EQ(message("wrinkling = true\nresidual_stiffness = 0.5\n", "0.2"),
            "case.toml:7: law.region[0].residual_stiffness: out of range (got 0.5, expected [0, 0.5))");
}

// A [test.mesh] value replaces [mesh]'s; fem's check of the test's mesh is placed at the table that
// gave the value.
TEST(CaseSpec, AMeshErrorIsPlacedAtTheTableThatGaveTheValue) {
  const char* text = "[mesh]\ngrading = 0.0\n[[test]]\nname = \"a\"\n[test.mesh]\nnx = 4\n";
  CaseSpec spec = CaseSpec::from_config(io::parse_config(case_schema(), text, "case.toml"));
  EXPECT_EQ(message_of([&] { spec.models(); }).rfind("case.toml:2: mesh.grading: ", 0), 0u)
      << message_of([&] { spec.models(); });
  spec.mesh.grading = 1;
  spec.test[0].mesh.grading = -1;  // set in code: the file's range would refuse it
  EXPECT_EQ(message_of([&] { spec.models(); }).rfind("case.toml:5: test[0].mesh.grading: ", 0), 0u)
      << message_of([&] { spec.models(); });
}

// [mesh] whole = true: a custom test on the generator gets the whole width × height rectangle centred
// on the origin (the frame of a full specimen between its clamps), its edges named as the quarter's.
TEST(CaseSpec, AWholeGeneratedMeshIsTheRectangleCentredOnTheOrigin) {
  const char* text = R"([mesh]
whole = true
width = 20
height = 60
nx = 2
ny = 4
[[test]]
name = "pull"
kind = "custom"
loads = [1]
[test.mesh]
width = 30
[[test.boundary]]
name = "bottom"
fix = ["x", "y"]
[[test.boundary]]
name = "top"
ux = [0]
uy = [3]
)";
  const CaseSpec spec = CaseSpec::from_config(io::parse_config(case_schema(), text, "case.toml"));
  const fem::TestModel t = spec.models().at(0);
  EXPECT_DOUBLE_EQ(t.mesh.X.row(0).minCoeff(), -15);  // [test.mesh] width replaces [mesh]'s
  EXPECT_DOUBLE_EQ(t.mesh.X.row(0).maxCoeff(), 15);
  EXPECT_DOUBLE_EQ(t.mesh.X.row(1).minCoeff(), -30);
  EXPECT_DOUBLE_EQ(t.mesh.X.row(1).maxCoeff(), 30);
  EXPECT_EQ(t.mesh.elements(), 2 * 4);  // nx × ny over the whole rectangle
  for (int n : t.mesh.boundary("top")) EXPECT_DOUBLE_EQ(t.mesh.X(1, n), 30);
  for (int n : t.mesh.boundary("bottom")) EXPECT_DOUBLE_EQ(t.mesh.X(1, n), -30);
}

}  // namespace
}  // namespace tricot::project
