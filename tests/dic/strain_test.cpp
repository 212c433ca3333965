#include "tricot/dic/strain.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::dic;

namespace {
/// An affine motion is fitted exactly; only round-off remains.
constexpr double kExact = 1e-12;
}  // namespace

TEST(GreenLagrange, AHomogeneousDeformationGivesItsExactStrainEverywhere) {
  const auto g = make_grid(Roi::whole_image(), 200, 200, 21, 10);
  Mat2 F;
  F << 2.2, 0.3, -0.1, 1.4;  // 120 % × 40 % stretch with some shear and rotation
  std::vector<Vec2> x(g.size());
  for (std::size_t k = 0; k < g.size(); ++k) x[k] = Vec2(5, -3) + F * g[k].x;
  const auto E = green_lagrange(g, x, std::vector<char>(g.size(), 1), StrainOptions{});
  const Mat2 expected = 0.5 * (F.transpose() * F - Mat2::Identity());
  for (const auto& s : E) {
    ASSERT_TRUE(s.valid);
    EXPECT_NEAR(s.exx, expected(0, 0), kExact);
    EXPECT_NEAR(s.eyy, expected(1, 1), kExact);
    EXPECT_NEAR(s.exy, expected(0, 1), kExact);
  }
}

TEST(GreenLagrange, ARigidRotationHasNoStrain) {
  const auto g = make_grid(Roi::whole_image(), 120, 120, 21, 10);
  const double t = 0.7;
  Mat2 R;
  R << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  std::vector<Vec2> x(g.size());
  for (std::size_t k = 0; k < g.size(); ++k) x[k] = R * g[k].x;
  for (const auto& s : green_lagrange(g, x, std::vector<char>(g.size(), 1), StrainOptions{})) {
    EXPECT_NEAR(s.exx, 0, kExact);
    EXPECT_NEAR(s.eyy, 0, kExact);
    EXPECT_NEAR(s.exy, 0, kExact);
  }
}

TEST(GreenLagrange, APointWithTooFewGoodNeighboursIsInvalid) {
  const auto g = make_grid(Roi::whole_image(), 120, 120, 21, 10);
  std::vector<Vec2> x(g.size());
  for (std::size_t k = 0; k < g.size(); ++k) x[k] = g[k].x;
  std::vector<char> good(g.size(), 0);
  good[0] = good[1] = good[2] = 1;  // three points on a line
  const auto E = green_lagrange(g, x, good, StrainOptions{});
  EXPECT_FALSE(E[1].valid);
  EXPECT_TRUE(std::isnan(E[1].exx));
  EXPECT_FALSE(E[5].valid);  // not good itself
}

TEST(StrainOptions, EvenWindowIsRejected) {
  StrainOptions o;
  o.window = 4;
  EXPECT_THROW(o.validate(), InputError);
}
