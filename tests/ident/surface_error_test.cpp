#include "tricot/ident/surface_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::ident;

namespace {
/// Sums of a few exact ratios: round-off only.
constexpr double kRoundOff = 1e-14;
}  // namespace

// A surface that is everywhere 1.2× the data has ē = 0.2 exactly; points outside the practical
// domain count only in the whole-range mean.
TEST(Eq9Error, IsTheMeanRelativeDistanceOverTheWholeAndThePracticalRange) {
  std::vector<SurfacePoint> points = {{0.1, 0.0, 0.02}, {0.7, 0.3, 0.2}, {0.9, 0.25, 0.3}, {0.5, 0.5, 0.1}};
  auto data_at = [&](double eC, double eW) {
    for (const auto& p : points)
      if (p.eC == eC && p.eW == eW) return p.force;
    return 0.0;
  };
  // 1.2× in the practical domain, 0.5× outside: ē_practical = 0.2, ē_whole = (0.2 + 0.2 + 0.5 + 0.5)/4.
  auto identified = [&](double eC, double eW) {
    return (StrainDomain{}.contains(eC, eW) ? 1.2 : 0.5) * data_at(eC, eW);
  };
  const Eq9Error e = eq9_error(points, identified);
  EXPECT_EQ(e.points_whole, 4);
  EXPECT_EQ(e.points_practical, 2);
  EXPECT_NEAR(e.practical, 0.2, kRoundOff);
  EXPECT_NEAR(e.whole, 0.35, kRoundOff);
}

TEST(Eq9Error, LeavesOutPointsWithoutForceAndRejectsAPracticalDomainOutsideTheData) {
  const std::vector<SurfacePoint> points = {{0.0, 0.0, 0.0}, {0.2, 0.1, 0.05}};
  auto same = [](double, double) { return 0.05; };
  try {
    eq9_error(points, same);
    FAIL() << "no point in [60, 100] % x [20, 40] %";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("eq9.practical"), std::string::npos) << e.what();
  }
  StrainDomain d;
  d.eC_min = 0.1, d.eC_max = 0.3, d.eW_min = 0, d.eW_max = 0.2;
  const Eq9Error e = eq9_error(points, same, d);
  EXPECT_EQ(e.points_whole, 1);
  EXPECT_EQ(e.whole, 0.0);
  d.eC_min = 0.5;  // min > max
  EXPECT_THROW(eq9_error(points, same, d), InputError);
}

// A homogeneous measured field u = G X gives the centre strain E = ½(FᵀF − I) exactly, mapped to
// (εC, εW) by the pull: wale pulled (angle 0) has course along x, course pulled (90) along y.
TEST(TestSurfacePoints, AreTheGripForcePerWidthAgainstTheCentreStrainOfTheMeasuredField) {
  constexpr double kFit = 1e-12;  // exact affine field: least squares reproduces it to round-off
  fem::TestModel model;
  fem::MeshOptions mo;
  mo.width = 55, mo.height = 55, mo.nx = 2, mo.ny = 2;
  model.mesh = fem::make_quarter_mesh(mo);
  TestData data;
  data.name = "t";
  data.loads = {1.0, 2.0};
  data.edge_force = {11.0, 22.0};
  data.points.resize(2, 4);
  data.points << 1, 10, 3, 20, 2, 4, 15, 30;
  const Eigen::Matrix2d G1 = (Eigen::Matrix2d() << 0.10, 0.02, -0.01, 0.30).finished();
  const Eigen::Matrix2d G2 = 2 * G1;
  data.u.resize(2, 4), data.v.resize(2, 4);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d u1 = G1 * data.points.col(i), u2 = G2 * data.points.col(i);
    data.u(0, i) = u1(0), data.v(0, i) = u1(1), data.u(1, i) = u2(0), data.v(1, i) = u2(1);
  }
  auto E_of = [](const Eigen::Matrix2d& G) {
    const Eigen::Matrix2d F = Eigen::Matrix2d::Identity() + G;
    return Eigen::Matrix2d(0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity()));
  };
  const auto wale = test_surface_points(model, data);
  ASSERT_TRUE(wale.has_value());
  EXPECT_EQ(wale->force, SurfaceForce::wale);
  ASSERT_EQ(wale->points.size(), 2u);
  EXPECT_NEAR(wale->points[1].eC, E_of(G2)(0, 0), kFit);
  EXPECT_NEAR(wale->points[1].eW, E_of(G2)(1, 1), kFit);
  EXPECT_NEAR(wale->points[0].force, 11.0 / 110.0, kFit);
  model.material_angle = 90;
  const auto course = test_surface_points(model, data);
  ASSERT_TRUE(course.has_value());
  EXPECT_EQ(course->force, SurfaceForce::course);
  EXPECT_NEAR(course->points[0].eC, E_of(G1)(1, 1), kFit);
  EXPECT_NEAR(course->points[0].eW, E_of(G1)(0, 0), kFit);
  model.material_angle = 45;  // neither surface
  EXPECT_FALSE(test_surface_points(model, data).has_value());
}
