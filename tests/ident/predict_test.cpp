// ident/predict.cpp: the FE's values at the measured steps and points, and how field values are
// stacked into the residual (docs/theory.md §7). White-box: the engine's private header.
#include "predict.hpp"

#include <gtest/gtest.h>

#include "tricot/fem/mesh.hpp"
#include "tricot/fem/neo_hookean.hpp"

namespace tricot::ident::detail {
namespace {

constexpr double kHomogeneous = 1e-10;  // a uniform field is reproduced by the FE to round-off (issue 2)

TEST(Stack, IsStepMajorWithThePointsInside) {
  Eigen::MatrixXd F(2, 3);
  F << 1, 2, 3, 4, 5, 6;  // steps × points
  Eigen::VectorXd expected(6);
  expected << 1, 2, 3, 4, 5, 6;
  EXPECT_EQ(stack(F), expected);
}

TEST(StackUv, InterleavesUAndVPointByPoint) {
  Eigen::MatrixXd U(2, 2), V(2, 2);
  U << 1, 2, 3, 4;
  V << -1, -2, -3, -4;
  Eigen::VectorXd expected(8);
  expected << 1, -1, 2, -2, 3, -3, 4, -4;
  EXPECT_EQ(stack_uv(U, V), expected);
}

TEST(Predict, GivesTheHomogeneousFieldAndItsCoefficientDerivativesVanishUnderDisplacementControl) {
  // Sliding grip, free side, displacement control: u_y = d · y / H whatever the law, so ∂v/∂c = 0.
  fem::MeshOptions o;
  o.width = 10, o.height = 20, o.nx = 2, o.ny = 3;
  fem::TestModel model;
  model.mesh = fem::make_quarter_mesh(o);
  model.grip_holds_x = false;
  model.loads = {1, 3};
  const fem::NeoHookean law(0.5, 1.0);
  fem::SolveOptions options;
  options.tolerance = 1e-13;
  options.sensitivities = true;
  const fem::SimulationResult sim = fem::simulate(model, law, options);
  ASSERT_TRUE(sim.usable()) << sim.message;

  TestData data;
  data.name = model.name;
  data.loads = model.loads;
  data.points.resize(2, 2);
  data.points << 2.5, 7.0, 5.0, 15.0;
  data.point_ids = {1, 2};
  data.u = data.v = Eigen::MatrixXd::Zero(2, 2);
  const std::vector<int> coefficients{0, 1};  // μ and λ
  Prediction p;
  std::string message;
  ASSERT_TRUE(predict(model, data, locate_points(model, data), sim, &coefficients, p, message)) << message;
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(p.edge_displacement(k), model.loads[k], kHomogeneous * model.loads[k]);
    for (int q = 0; q < 2; ++q) {
      EXPECT_NEAR(p.V(k, q), model.loads[k] * data.points(1, q) / 20, kHomogeneous * model.loads[k]);
      for (int c = 0; c < 2; ++c) EXPECT_NEAR(p.dV_dc(k * 2 + q, c), 0, kHomogeneous);
    }
  }
}

}  // namespace
}  // namespace tricot::ident::detail
