// ident/synthetic.cpp: the measurements an FE run gives, σ as a fraction of each group's RMS, and
// reproducible Gaussian noise.
#include "tricot/ident/synthetic.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tricot/fem/mesh.hpp"
#include "tricot/fem/neo_hookean.hpp"

namespace tricot::ident {
namespace {

constexpr double kExact = 1e-15;        // sums of a few squares: round-off only
constexpr double kHomogeneous = 1e-10;  // a uniform field is reproduced by the FE to round-off (issue 2)

TestData small_data() {
  TestData d;
  d.name = "t";
  d.loads = {1, 2, 3};
  d.edge_displacement = {3, 4, 0};
  d.points = Eigen::Matrix2Xd::Zero(2, 2);
  d.point_ids = {1, 2};
  d.u = Eigen::MatrixXd::Constant(3, 2, 1.0);
  d.v = Eigen::MatrixXd::Constant(3, 2, 1.0);
  d.v(2, 1) = 7;
  return d;
}

TEST(RmsFraction, IsTheFractionOfEachGroupsRootMeanSquare) {
  const Sigma s = rms_fraction(small_data(), 0.01);
  EXPECT_NEAR(s.edge_displacement, 0.01 * std::sqrt(25.0 / 3), kExact);
  EXPECT_EQ(s.edge_force, 0);  // not measured
  // u and v together: eleven values 1 and one 7.
  EXPECT_NEAR(s.field, 0.01 * std::sqrt((11.0 + 49.0) / 12), kExact);
}

TEST(AddNoise, IsReproducibleForASeedAndLeavesAZeroSigmaGroupAlone) {
  TestData a = small_data(), b = small_data();
  const Sigma sigma{0.1, 0, 0.2};
  add_noise(a, sigma, 7);
  add_noise(b, sigma, 7);
  EXPECT_EQ(a.edge_displacement, b.edge_displacement);
  EXPECT_EQ(a.u, b.u);
  EXPECT_EQ(a.v, b.v);
  EXPECT_NE(a.edge_displacement, small_data().edge_displacement);
  EXPECT_EQ(a.sigma.edge_displacement, 0.1);
  EXPECT_EQ(a.sigma.field, 0.2);
  TestData c = small_data();
  add_noise(c, {0, 0, 0}, 7);
  EXPECT_EQ(c.edge_displacement, small_data().edge_displacement);
  EXPECT_EQ(c.u, small_data().u);
}

TEST(AddNoise, HasTheRequestedStandardDeviation) {
  constexpr int kN = 20000;
  // The sample σ of N Gaussian values has a standard error σ/√(2N) = 0.5 % here: 3 % is 6 of them.
  constexpr double kSampleSigma = 0.03;
  TestData d;
  d.loads.assign(kN, 1.0);
  d.edge_displacement.assign(kN, 0.0);
  add_noise(d, {0.3, 0, 0}, 20070101);
  double sum = 0, sum2 = 0;
  for (double x : d.edge_displacement) sum += x, sum2 += x * x;
  const double mean = sum / kN, sd = std::sqrt(sum2 / kN - mean * mean);
  EXPECT_NEAR(sd, 0.3, kSampleSigma * 0.3);
  EXPECT_NEAR(mean, 0, 6 * 0.3 / std::sqrt(double(kN)));
}

TEST(Measure, TakesTheGripAndTheFieldOfAHomogeneousTest) {
  // Sliding grip, free side: u_y = d · y / H at every point, whatever the law (docs/theory.md §6).
  fem::MeshOptions o;
  o.width = 10, o.height = 20, o.nx = 2, o.ny = 3;
  fem::TestModel model;
  model.mesh = fem::make_quarter_mesh(o);
  model.grip_holds_x = false;
  model.loads = {1, 2, 4};
  const fem::NeoHookean law(0.5, 1.0);
  fem::SolveOptions tight;
  tight.tolerance = 1e-13;
  const fem::SimulationResult sim = fem::simulate(model, law, tight);
  ASSERT_TRUE(sim.usable()) << sim.message;
  Eigen::Matrix2Xd points(2, 2);
  points << 2.5, 7.0, 5.0, 15.0;
  const TestData d = measure(model, sim, points, {4, 9});
  ASSERT_EQ(d.steps(), 3);
  EXPECT_EQ(d.point_ids, (std::vector<int>{4, 9}));
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(d.edge_displacement[k], model.loads[k], kHomogeneous * model.loads[k]);
    EXPECT_EQ(d.edge_force[k], sim.steps[k].edge_force);
    for (int p = 0; p < 2; ++p)
      EXPECT_NEAR(d.v(k, p), model.loads[k] * points(1, p) / 20, kHomogeneous * model.loads[k]) << k << " " << p;
  }
}

}  // namespace
}  // namespace tricot::ident
