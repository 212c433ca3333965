// `tricot simulate` on any specimen (issue 28, docs/theory.md §6): a Gmsh geometry meshed at run time, tests of
// kind = "custom" with [[test.boundary]] conditions, their resultants in steps.csv, VTU files that
// meshio reads for every element type, and one clear line for each kind of bad input.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "testing/cli.hpp"
#include "testing/meshio.hpp"
#include "tricot/io/files.hpp"

namespace tricot {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;

constexpr double kHomogeneous = 1e-9;  // a homogeneous state on any mesh: Newton's tolerance, 1e-10

// A 20 × 50 mm rectangle with its four sides named.
const char* kRectangle = R"(
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 20, 50};
eps = 1e-6;
Physical Surface("sheet") = {1};
Physical Curve("bottom") = Curve In BoundingBox{-eps, -eps, -eps, 20 + eps, eps, eps};
Physical Curve("top") = Curve In BoundingBox{-eps, 50 - eps, -eps, 20 + eps, 50 + eps, eps};
Physical Curve("left") = Curve In BoundingBox{-eps, -eps, -eps, eps, 50 + eps, eps};
Physical Curve("right") = Curve In BoundingBox{20 - eps, -eps, -eps, 20 + eps, 50 + eps, eps};
sides() = Curve In BoundingBox{-eps, -eps, -eps, eps, 50 + eps, eps};
sides() += Curve In BoundingBox{20 - eps, -eps, -eps, 20 + eps, 50 + eps, eps};
Physical Curve("sides") = {sides()};
)";

// A plane-strain neo-Hookean sheet held across (left and right u_x = 0), its bottom held along y and
// its top pulled by 10 and 20 mm: F = diag(1, λ), P22 = μ (λ − 1/λ) + λ_L ln λ / λ.
std::string held_sheet(const std::string& element, const std::string& top = "top") {
  return fmt::format(R"(
[mesh]
geometry = "rect.geo"
element = "{}"
size = 6.0

[law]
type = "neo_hookean"

[law.neo_hookean]
mu = 0.8
lambda = 2.5
kinematics = "plane_strain"

[[test]]
name = "held"
kind = "custom"
steps = 2

[[test.boundary]]
name = "left"
fix = ["x"]

[[test.boundary]]
name = "right"
symmetry = true

[[test.boundary]]
name = "bottom"
fix = ["y"]

[[test.boundary]]
name = "{}"
uy = [10, 20]
force = "y"
)",
                     element, top);
}

fs::path write_case(const std::string& name, const std::string& text) {
  const fs::path dir = test::scratch_dir("custom_" + name);
  std::ofstream(dir / "rect.geo") << kRectangle;
  std::ofstream(dir / "case.toml") << text;
  return dir / "case.toml";
}

TEST(CustomSpecimen, AGmshSheetHeldAcrossGivesThePlaneStrainClosedFormOnEveryElementType) {
  for (const char* element : {"T3", "T6", "Q4", "Q8"}) {
    SCOPED_TRACE(element);
    const fs::path c = write_case(std::string("held_") + element, held_sheet(element));
    const fs::path out = c.parent_path() / "out";
    const auto r = run_tricot("simulate " + c.string() + " -o " + out.string() + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const io::Table t = io::read_csv(out / "held" / "steps.csv");
    const std::vector<double> force = t.values("edge_force"), top = t.values("resultant_y_top"),
                              bottom = t.values("resultant_y_bottom");
    for (int k = 0; k < 2; ++k) {
      const double l = 1 + 10.0 * (k + 1) / 50, P22 = 0.8 * (l - 1 / l) + 2.5 * std::log(l) / l;
      EXPECT_NEAR(force[k], P22 * 20, kHomogeneous * P22 * 20);
      EXPECT_NEAR(top[k], force[k], kHomogeneous * force[k]);
      EXPECT_NEAR(bottom[k], -force[k], kHomogeneous * force[k]);
    }
    if (!test::have_meshio()) continue;
    const std::string cells = test::read_with_meshio(out / "held" / "step_0002.vtu", "print(m.cells[0].type)\n");
    const std::map<std::string, std::string> expected = {
        {"T3", "triangle"}, {"T6", "triangle6"}, {"Q4", "quad"}, {"Q8", "quad8"}};
    EXPECT_EQ(cells, expected.at(element) + "\n");
  }
}

// The top pulled through compliant ties (t = 0.04 N/mm per mm) instead of rigidly: the sheet and the
// ties are springs in series. The held sheet stays homogeneous, F = diag(1, λ), and its force is also
// the ties' t · width · (d − (λ − 1) L): λ solves 20 P22(λ) = 0.04 · 20 (d − 50 (λ − 1)) (bisection).
TEST(CustomSpecimen, ATiedGripIsASpringInSeriesWithTheSheet) {
  for (const char* element : {"T3", "T6", "Q4", "Q8"}) {
    SCOPED_TRACE(element);
    std::string text = held_sheet(element);
    text.replace(text.find("force = \"y\""), 11, "force = \"y\"\ntie = 0.04");
    const fs::path c = write_case(std::string("tied_") + element, text);
    const fs::path out = c.parent_path() / "out";
    const auto r = run_tricot("simulate " + c.string() + " -o " + out.string() + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const io::Table t = io::read_csv(out / "held" / "steps.csv");
    const std::vector<double> force = t.values("edge_force");
    for (int k = 0; k < 2; ++k) {
      const double d = 10.0 * (k + 1);
      auto P22 = [](double l) { return 0.8 * (l - 1 / l) + 2.5 * std::log(l) / l; };
      auto gap = [&](double l) { return P22(l) - 0.04 * (d - 50 * (l - 1)); };
      double lo = 1, hi = 1 + d / 50;  // gap(lo) < 0 < gap(hi)
      for (int i = 0; i < 200; ++i) (gap(0.5 * (lo + hi)) < 0 ? lo : hi) = 0.5 * (lo + hi);
      const double expected = 20 * P22(0.5 * (lo + hi));
      EXPECT_NEAR(force[k], expected, kHomogeneous * expected);
      EXPECT_LT(force[k], 0.5 * 20 * P22(1 + d / 50));  // far below the rigid grip's force
    }
  }
}

// A compressible Mooney–Rivlin sheet (kappa > 0) held across in plane strain: F = diag(1, λ), C33 = 1,
// and the force is the width times dW/dλ of W = C10 (Ī1 − 3) + C01 (Ī2 − 3) + κ/2 (ln J)² written
// here (central differences, h = 1e-6).
TEST(CustomSpecimen, ACompressibleMooneyRivlinSheetHeldAcrossGivesItsEnergysForce) {
  std::string text = held_sheet("T6");
  const std::string law = "[law.neo_hookean]\nmu = 0.8\nlambda = 2.5\nkinematics = \"plane_strain\"\n";
  text.replace(text.find(law), law.size(),
               "[law.mooney_rivlin]\nterms = [\"C10\", \"C01\"]\nvalues = [0.3, 0.1]\nkappa = 3.0\n"
               "kinematics = \"plane_strain\"\n");
  text.replace(text.find("type = \"neo_hookean\""), 20, "type = \"mooney_rivlin\"");
  const fs::path c = write_case("mooney_compressible", text);
  const fs::path out = c.parent_path() / "out";
  const auto r = run_tricot("simulate " + c.string() + " -o " + out.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<double> force = io::read_csv(out / "held" / "steps.csv").values("edge_force");
  auto W = [](double l) {
    const double I1 = 2 + l * l, I2 = 1 + 2 * l * l, I3 = l * l;
    return 0.3 * (I1 / std::cbrt(I3) - 3) + 0.1 * (I2 / std::pow(I3, 2.0 / 3) - 3) + 1.5 * std::pow(std::log(l), 2);
  };
  for (int k = 0; k < 2; ++k) {
    const double l = 1 + 10.0 * (k + 1) / 50, h = 1e-6, expected = 20 * (W(l + h) - W(l - h)) / (2 * h);
    EXPECT_NEAR(force[k], expected, 1e-7 * expected);
  }
}

// Two materials in series ([[law.region]]): a 20 × 50 mm sheet, its lower 30 mm "soft" (the [law]) and
// its upper 20 mm "stiff" (a region law), held across in plane strain and pulled. Each part is
// homogeneous, F = diag(1, λ_i), with the same force per width p = P22(λ_soft) = P22(λ_stiff) and
// 30 (λ_soft − 1) + 20 (λ_stiff − 1) = d: p by bisection.
const char* kTwoMaterials = R"(
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 20, 30};
Rectangle(2) = {0, 30, 0, 20, 20};
BooleanFragments{ Surface{1, 2}; Delete; }{}
eps = 1e-6;
Physical Surface("soft") = Surface In BoundingBox{-eps, -eps, -eps, 20 + eps, 30 + eps, eps};
Physical Surface("stiff") = Surface In BoundingBox{-eps, 30 - eps, -eps, 20 + eps, 50 + eps, eps};
Physical Curve("bottom") = Curve In BoundingBox{-eps, -eps, -eps, 20 + eps, eps, eps};
Physical Curve("top") = Curve In BoundingBox{-eps, 50 - eps, -eps, 20 + eps, 50 + eps, eps};
Physical Curve("left") = Curve In BoundingBox{-eps, -eps, -eps, eps, 50 + eps, eps};
Physical Curve("right") = Curve In BoundingBox{20 - eps, -eps, -eps, 20 + eps, 50 + eps, eps};
)";

std::string two_materials(const std::string& region) {
  std::string text = held_sheet("T3");
  text += "\n[[law.region]]\nname = \"" + region +
          "\"\ntype = \"neo_hookean\"\n\n[law.region.neo_hookean]\nmu = 2.0\n"
          "lambda = 4.0\nkinematics = \"plane_strain\"\n";
  return text;
}

TEST(CustomSpecimen, TwoMaterialsInSeriesGiveTheClosedFormAndAnUnknownRegionIsNamed) {
  const fs::path c = write_case("two_materials", two_materials("stiff"));
  std::ofstream(c.parent_path() / "rect.geo") << kTwoMaterials;
  const fs::path out = c.parent_path() / "out";
  const auto r = run_tricot("simulate " + c.string() + " -o " + out.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<double> force = io::read_csv(out / "held" / "steps.csv").values("edge_force");
  auto P22 = [](double l, double mu, double lam) { return mu * (l - 1 / l) + lam * std::log(l) / l; };
  auto stretch = [&](double p, double mu, double lam) {  // P22(λ) = p, P22 increasing
    double lo = 1, hi = 10;
    for (int i = 0; i < 200; ++i) (P22(0.5 * (lo + hi), mu, lam) < p ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
  };
  for (int k = 0; k < 2; ++k) {
    const double d = 10.0 * (k + 1);
    double lo = 0, hi = 100;
    for (int i = 0; i < 200; ++i) {
      const double p = 0.5 * (lo + hi);
      (30 * (stretch(p, 0.8, 2.5) - 1) + 20 * (stretch(p, 2.0, 4.0) - 1) < d ? lo : hi) = p;
    }
    const double expected = 20 * 0.5 * (lo + hi);
    EXPECT_NEAR(force[k], expected, kHomogeneous * expected);
  }
  std::string untyped = two_materials("stiff");  // a region table without its type
  untyped.replace(untyped.find("type = \"neo_hookean\"\n\n[law.region.neo_hookean]"), 20, "");
  const fs::path no_type = write_case("two_materials_no_type", untyped);
  std::ofstream(no_type.parent_path() / "rect.geo") << kTwoMaterials;
  const auto t = run_tricot("simulate " + no_type.string() + " -o " + (no_type.parent_path() / "out").string());
  EXPECT_EQ(t.exit_code, 2);
  EXPECT_NE(t.err.find("law.region[0].type: a region's law needs its type"), std::string::npos) << t.err;
  const fs::path bad = write_case("two_materials_typo", two_materials("stif"));
  std::ofstream(bad.parent_path() / "rect.geo") << kTwoMaterials;
  const auto b = run_tricot("simulate " + bad.string() + " -o " + (bad.parent_path() / "out").string());
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("law.region[0].name: no region of the mesh is named 'stif' (did you mean 'stiff'?)"),
            std::string::npos)
      << b.err;
  EXPECT_FALSE(fs::exists(bad.parent_path() / "out"));
}

// A geometry Gmsh cannot build (OpenCASCADE's ellipse takes its larger radius first) is one line naming
// the file and Gmsh's reason, exit 3, not a crash (libgmsh throws its errors as strings).
TEST(CustomSpecimen, AGeometryGmshCannotBuildIsNamedWithGmshsReason) {
  const fs::path c = write_case("broken_geo", held_sheet("T3"));
  std::ofstream(c.parent_path() / "rect.geo") << "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 20, 50};\n"
                                                 "Disk(2) = {10, 25, 0, 3, 6};\n"
                                                 "BooleanFragments{ Surface{1}; Delete; }{ Surface{2}; Delete; }\n";
  const auto r = run_tricot("simulate " + c.string() + " -o " + (c.parent_path() / "out").string());
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("rect.geo"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Gmsh cannot read it"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(CustomSpecimen, TheStripWithAHoleExampleBalancesItsClampsAndComesBackUnloaded) {
  const fs::path out = test::scratch_dir("custom_strip") / "out";
  const auto r = run_tricot("simulate " + (test::source_dir() / "examples/strip-with-hole/case.toml").string() +
                            " -o " + out.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Table t = io::read_csv(out / "one-sided" / "steps.csv");
  const std::vector<double> f = t.values("edge_force"), fx_top = t.values("resultant_x_top"),
                            fy_bottom = t.values("resultant_y_bottom"), fx_bottom = t.values("resultant_x_bottom");
  const double peak = f[2];
  ASSERT_GT(peak, 0);
  for (std::size_t k = 0; k < f.size(); ++k) {  // equilibrium of the whole strip, along y and x
    EXPECT_NEAR(fy_bottom[k], -f[k], kHomogeneous * peak);
    EXPECT_NEAR(fx_bottom[k], -fx_top[k], kHomogeneous * peak);
  }
  EXPECT_GT(std::abs(fx_top[2]), 1e-4 * peak);  // the hole off the axis pulls the clamps sideways
  EXPECT_EQ(f[3], f[2]);                        // a hold: the same state
  EXPECT_NEAR(f[5], 0, kHomogeneous * peak);    // back at 0 mm: unloaded
}

TEST(CustomSpecimen, BadInputIsOneLineNamingTheFileKeyAndValueAndWritesNothing) {
  struct Case {
    std::string name, text, expect;
  };
  std::string no_such = held_sheet("T3", "tpo");
  std::string short_series = held_sheet("T3");
  short_series.replace(short_series.find("uy = [10, 20]"), 13, "uy = [10]");
  std::string not_custom = held_sheet("T3");
  not_custom.replace(not_custom.find("kind = \"custom\""), 15, "kind = \"uniaxial\"");
  std::string missing = held_sheet("T3");
  missing.replace(missing.find("rect.geo"), 8, "none.geo");
  std::string two_lines = held_sheet("T3");  // a guide that ends on two separate lines
  two_lines.replace(two_lines.find("name = \"left\"\nfix = [\"x\"]"), 25,
                    "name = \"sides\"\nfix = [\"x\"]\ntie = 1.0\ntie_end = [0, 40]");
  std::string taper = held_sheet("T3");  // a taper with no end to fall toward
  taper.replace(taper.find("force = \"y\""), 11, "force = \"y\"\ntie = 1.0\ntie_taper = 5.0");
  std::string both_pairs = held_sheet("T3");  // (E, ν) and (μ, λ) at once
  both_pairs.replace(both_pairs.find("lambda = 2.5"), 12, "lambda = 2.5\nE = 2.0\nnu = 0.3");
  const Case cases[] = {
      {"both_pairs", both_pairs, "law.neo_hookean.mu: give E and nu, or mu and lambda, not both"},
      {"tie_two_lines", two_lines,
       "test[0].boundary[0].tie_end: test 'held': a tie that ends needs the boundary 'sides' to be one open line"},
      {"tie_taper", taper, "test[0].boundary[3].tie_taper: a taper needs the tie's end"},
      {"unknown_boundary", no_such,
       "test[0].boundary[3].name: no boundary of the mesh is named 'tpo' (did you mean 'top'?)"},
      {"short_series", short_series, "test[0].boundary[3].uy: the series of boundary 'top' has 1 values for 2 steps"},
      {"not_custom", not_custom, "mesh.geometry: a Gmsh mesh is for tests of kind = \"custom\""},
      {"missing", missing, "mesh.geometry:"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path file = write_case(c.name, c.text);
    const fs::path out = file.parent_path() / "out";
    const auto r = run_tricot("simulate " + file.string() + " -o " + out.string());
    EXPECT_EQ(r.exit_code, c.name == "missing" ? 3 : 2) << r.err;
    EXPECT_NE(r.err.find(file.string() + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out)) << "an output folder was left";
  }
}

}  // namespace
}  // namespace tricot
