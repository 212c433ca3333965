// project/fem_vtu.cpp: the tension-field fields of a wrinkling law's VTU (issue 30).
#include "tricot/project/fem_vtu.hpp"

#include <gtest/gtest.h>

#include <string>

#include "tricot/fem/mesh.hpp"
#include "tricot/fem/neo_hookean.hpp"
#include "tricot/fem/wrinkling.hpp"

namespace tricot::project {
namespace {

/// The field called `name` of the grid's cells, or nullptr.
const io::VtuField* cell_field(const io::VtuGrid& g, const std::string& name) {
  for (const auto& f : g.cell_data)
    if (f.name == name) return &f;
  return nullptr;
}

/// u of the homogeneous state F = diag(l1, l2) on the mesh.
Eigen::VectorXd homogeneous(const fem::Mesh& mesh, double l1, double l2) {
  Eigen::VectorXd u(mesh.dofs());
  for (int a = 0; a < mesh.nodes(); ++a) u.segment<2>(2 * a) = Vec2((l1 - 1) * mesh.X(0, a), (l2 - 1) * mesh.X(1, a));
  return u;
}

TEST(FemVtu, AWrinklingLawWritesTheWrinkledAndSlackFractionsAndTheWrinkleDirection) {
  fem::MeshOptions o;
  o.type = fem::ElementType::Q8, o.nx = 2, o.ny = 2, o.width = 10, o.height = 10;
  const fem::Mesh mesh = fem::make_quarter_mesh(o);
  const fem::NeoHookean inner(0.1, 0.2);
  const fem::WrinklingLaw law(inner);
  // Pulled along x, squeezed across (as in wrinkling_test.cpp): every point wrinkled along x.
  const io::VtuGrid g = fem_vtu_grid(mesh, homogeneous(mesh, 1.3, 0.8), law, 0);
  const io::VtuField* wrinkled = cell_field(g, "wrinkled_fraction");
  const io::VtuField* slack = cell_field(g, "slack_fraction");
  const io::VtuField* direction = cell_field(g, "wrinkle_direction");
  ASSERT_TRUE(wrinkled && slack && direction);
  for (int e = 0; e < mesh.elements(); ++e) {
    EXPECT_DOUBLE_EQ(wrinkled->values[e], 1.0);
    EXPECT_DOUBLE_EQ(slack->values[e], 0.0);
    EXPECT_NEAR(std::abs(direction->values[3 * e]), 1.0, 1e-12);
    EXPECT_NEAR(direction->values[3 * e + 1], 0.0, 1e-12);
  }
  // Squeezed both ways: slack.
  const io::VtuGrid s = fem_vtu_grid(mesh, homogeneous(mesh, 0.9, 0.8), law, 0);
  for (int e = 0; e < mesh.elements(); ++e) EXPECT_DOUBLE_EQ(cell_field(s, "slack_fraction")->values[e], 1.0);
  // The law alone writes no such field.
  EXPECT_EQ(cell_field(fem_vtu_grid(mesh, homogeneous(mesh, 1.3, 0.8), inner, 0), "wrinkled_fraction"), nullptr);
}

}  // namespace
}  // namespace tricot::project
