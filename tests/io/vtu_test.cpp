// The VTU writer is checked against a real reader: Debian's python3-meshio opens each file and prints
// what it found (point count, cell type, field values), which the test compares with what was written.
#include "tricot/io/vtu.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "testing/meshio.hpp"
#include "testing/paths.hpp"

namespace tricot::io {
namespace {

// The text is decimal with the shortest round-trip digits, so a reader gets the same doubles back.
constexpr double kRoundTrip = 0;

// Two Q8 cells side by side on [0, 2] × [0, 1]: 13 points (corners, then mid-sides).
VtuGrid two_quadratic_quads() {
  // Corners 0..5 on a 3 × 2 grid, mid-sides 6..12.
  const double P[13][2] = {{0, 0},   {1, 0},   {2, 0},   {0, 1},   {1, 1},   {2, 1},  // corners
                           {0.5, 0}, {1.5, 0}, {1, 0.5}, {2, 0.5}, {0.5, 1}, {1.5, 1}, {0, 0.5}};
  VtuGrid g;
  for (const auto& p : P) g.points.insert(g.points.end(), {p[0] + 0.1 * p[1], p[1], 0.0});
  g.cell_type = VtkCell::quadratic_quad;
  g.connectivity = {0, 1, 4, 3, 6, 8, 10, 12,  // corners ccw, then mid-sides 0-1, 1-2, 2-3, 3-0
                    1, 2, 5, 4, 7, 9, 11, 8};
  VtuField u{"displacement", 3, {}};
  for (int i = 0; i < 13; ++i) u.values.insert(u.values.end(), {0.1 * P[i][1], 0.25 * i, 0.0});
  VtuField s{"cauchy_stress", 9, {}};
  for (int c = 0; c < 2; ++c) s.values.insert(s.values.end(), {1.5 + c, 0.3, 0, 0.3, -2.25, 0, 0, 0, 0});
  VtuField id{"element", 1, {1, 2}};
  g.point_data = {u};
  g.cell_data = {s, id};
  return g;
}

using test::have_meshio;
using test::read_with_meshio;

class VtuFormats : public ::testing::TestWithParam<VtuFormat> {};

TEST_P(VtuFormats, MeshioReadsQuadraticQuadsWithTheirFields) {
  if (!have_meshio()) GTEST_SKIP() << "python3 lacks meshio (apt-get install python3-meshio)";
  const auto dir = test::scratch_dir(GetParam() == VtuFormat::ascii ? "vtu_q8_ascii" : "vtu_q8_binary");
  VtuGrid g = two_quadratic_quads();
  g.cell_data[1].values[0] = std::numeric_limits<double>::quiet_NaN();  // a failed element's value
  write_vtu(dir / "grid.vtu", g, GetParam());
  const std::string out = read_with_meshio(dir / "grid.vtu", R"(
print(len(m.points), len(m.cells), m.cells[0].type, len(m.cells[0].data))
print(" ".join(str(int(i)) for i in m.cells[0].data[1]))
print(repr(float(m.point_data["displacement"][7][1])), repr(float(m.points[10][0])))
s = m.cell_data["cauchy_stress"][0]
print(s.shape[1], repr(float(s[1][0])), repr(float(s[1][4])), repr(float(m.cell_data["element"][0][1])))
print(str(float(m.cell_data["element"][0][0])))
)");
  std::istringstream in(out);
  std::size_t points = 0, blocks = 0, cells = 0;
  std::string type;
  in >> points >> blocks >> type >> cells;
  EXPECT_EQ(points, 13u) << out;
  EXPECT_EQ(blocks, 1u) << out;
  EXPECT_EQ(type, "quad8") << out;
  EXPECT_EQ(cells, 2u) << out;
  int node[8];
  for (int& n : node) in >> n;
  for (int k = 0; k < 8; ++k) EXPECT_EQ(node[k], g.connectivity[8 + k]) << "node " << k;
  double u7y = 0, x10 = 0, s_xx = 0, s_yy = 0, element = 0;
  int components = 0;
  in >> u7y >> x10 >> components >> s_xx >> s_yy >> element;
  EXPECT_NEAR(u7y, 0.25 * 7, kRoundTrip);
  EXPECT_NEAR(x10, 0.5 + 0.1, kRoundTrip);
  EXPECT_EQ(components, 9);
  EXPECT_NEAR(s_xx, 2.5, kRoundTrip);
  EXPECT_NEAR(s_yy, -2.25, kRoundTrip);
  EXPECT_NEAR(element, 2, kRoundTrip);
  std::string nan;
  in >> nan;
  EXPECT_EQ(nan, "nan") << out;
}

INSTANTIATE_TEST_SUITE_P(BothFormats, VtuFormats, ::testing::Values(VtuFormat::binary, VtuFormat::ascii));

// A 40 × 40 Q8 grid with a smooth displacement and a non-round stress, as the FE writes: the
// compressed binary file must be much smaller than the text (the point of the format).
TEST(Vtu, BinaryIsAtMostHalfTheSizeOfTheText) {
  constexpr int kSide = 81;  // 40 × 40 Q8 on an 81 × 81 node lattice (corners and mid-sides)
  VtuGrid g;
  g.cell_type = VtkCell::quadratic_quad;
  VtuField u{"displacement", 3, {}};
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      g.points.insert(g.points.end(), {0.1 * i, 0.1 * j, 0.0});
      u.values.insert(u.values.end(), {std::sin(0.037 * i * j), 0.013 * j * j, 0.0});
    }
  VtuField s{"cauchy_stress", 9, {}};
  const auto at = [](int i, int j) { return j * kSide + i; };
  for (int ej = 0; ej < 40; ++ej)
    for (int ei = 0; ei < 40; ++ei) {
      const int i = 2 * ei, j = 2 * ej;
      g.connectivity.insert(g.connectivity.end(), {at(i, j), at(i + 2, j), at(i + 2, j + 2), at(i, j + 2), at(i + 1, j),
                                                   at(i + 2, j + 1), at(i + 1, j + 2), at(i, j + 1)});
      const double x = std::exp(0.01 * (ei + 40 * ej));
      s.values.insert(s.values.end(), {x, x / 3, 0, x / 3, x / 7, 0, 0, 0, 0});
    }
  g.point_data = {u};
  g.cell_data = {s};
  const std::size_t binary = to_vtu(g, VtuFormat::binary).size(), ascii = to_vtu(g, VtuFormat::ascii).size();
  EXPECT_LT(2 * binary, ascii) << "binary " << binary << " B, ascii " << ascii << " B";
}

TEST(Vtu, MeshioReadsLinearQuads) {
  if (!have_meshio()) GTEST_SKIP() << "python3 lacks meshio (apt-get install python3-meshio)";
  const auto dir = test::scratch_dir("vtu_q4");
  VtuGrid g;
  g.points = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  g.cell_type = VtkCell::quad;
  g.connectivity = {0, 1, 2, 3};
  g.point_data = {{"displacement", 3, {0, 0, 0, 0.5, 0, 0, 0.5, 0.2, 0, 0, 0.2, 0}}};
  write_vtu(dir / "quad.vtu", g);
  const std::string out = read_with_meshio(dir / "quad.vtu", R"(
print(len(m.points), m.cells[0].type, len(m.cells[0].data), repr(float(m.point_data["displacement"][2][1])))
)");
  std::istringstream in(out);
  std::size_t points = 0, cells = 0;
  std::string type;
  double u2y = 0;
  in >> points >> type >> cells >> u2y;
  EXPECT_EQ(points, 4u) << out;
  EXPECT_EQ(type, "quad") << out;
  EXPECT_EQ(cells, 1u) << out;
  EXPECT_NEAR(u2y, 0.2, kRoundTrip);
}

TEST(Vtu, FieldDataIsWrittenBeforeThePieceAndMeshioReadsItBack) {
  // Issue 16: a run's settings (tricot dic's virtual strain gauge) travel with the grid.
  VtuGrid g;
  g.points = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  g.connectivity = {0, 1, 2, 3};
  g.field_data = {{"vsg_px", 1, {71}}, {"pair", 1, {0.25, -3}}};
  const std::string text = to_vtu(g, VtuFormat::binary);
  EXPECT_NE(text.find("<FieldData>"), std::string::npos);
  EXPECT_LT(text.find("<FieldData>"), text.find("<Piece"));
  EXPECT_NE(text.find("Name=\"vsg_px\" NumberOfTuples=\"1\" format=\"ascii\"> 71 </DataArray>"), std::string::npos)
      << text;
  if (!have_meshio()) GTEST_SKIP() << "python3 lacks meshio (apt-get install python3-meshio)";
  const auto dir = test::scratch_dir("vtu_field_data");
  write_vtu(dir / "f.vtu", g);
  const std::string out = read_with_meshio(dir / "f.vtu", R"(
import numpy as np
print(repr(float(np.ravel(m.field_data["vsg_px"])[0])), repr(float(np.ravel(m.field_data["pair"])[1])))
)");
  std::istringstream in(out);
  double vsg = 0, second = 0;
  in >> vsg >> second;
  EXPECT_EQ(vsg, 71) << out;
  EXPECT_EQ(second, -3) << out;
}

TEST(Vtu, CollectionListsEveryStepWithItsTime) {
  const auto dir = test::scratch_dir("vtu_pvd");
  write_pvd(dir / "steps.pvd", {{0.5, "step_0001.vtu"}, {1.0, "step_0002.vtu"}});
  std::stringstream text;
  text << std::ifstream(dir / "steps.pvd").rdbuf();
  EXPECT_NE(text.str().find("timestep=\"0.5\" part=\"0\" file=\"step_0001.vtu\""), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("timestep=\"1\" part=\"0\" file=\"step_0002.vtu\""), std::string::npos) << text.str();
}

TEST(Vtu, InconsistentArraysAreRejectedBeforeWriting) {
  VtuGrid g = two_quadratic_quads();
  g.connectivity.back() = 13;  // no such point
  EXPECT_THROW(to_vtu(g), std::invalid_argument);
  g = two_quadratic_quads();
  g.cell_data[0].values.pop_back();
  EXPECT_THROW(to_vtu(g), std::invalid_argument);
  g = two_quadratic_quads();
  g.points.push_back(0);
  EXPECT_THROW(to_vtu(g), std::invalid_argument);
}

}  // namespace
}  // namespace tricot::io
