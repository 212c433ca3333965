#include "tricot/ident/surface_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
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
// Held levels: groups of the points' transverse strains whose sorted neighbours lie within 0.05.
TEST(HeldLevels, CountTheTransverseStrainsTheTestsProbeTheSurfaceAt) {
  auto at = [](std::initializer_list<double> held) {
    std::vector<SurfacePoint> p;
    for (double h : held) p.push_back({0.5, 0.3, 1.0, h});
    return p;
  };
  EXPECT_EQ(held_levels({}), 0);
  EXPECT_EQ(held_levels(at({std::nan("")})), 0);
  // Five repeats of a uniaxial test (their free sides narrow alike): one level.
  EXPECT_EQ(held_levels(at({0.0, 0.004, -0.01, 0.02, 0.011})), 1);
  // The campaign's course pulls held at 0, 0.15, 0.3, 0.45, 0.6, each with 21 steps.
  std::vector<SurfacePoint> campaign;
  for (double h : {0.0, 0.15, 0.3, 0.45, 0.6})
    for (int k = 0; k < 21; ++k) campaign.push_back({0.05 * k, h, 0.1 * k, h});
  EXPECT_EQ(held_levels(campaign), 5);
  EXPECT_EQ(held_levels(at({0.0, 0.04, 0.08, 0.3})), 2);  // a chain 0.04 apart is one level
  EXPECT_EQ(held_levels(at({0.0, 0.3}), 0.5), 1);         // the tolerance
}

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
  // Every point carries its test's transverse level: the strain across the pull at the first step.
  for (const auto& p : wale->points) EXPECT_NEAR(p.held, E_of(G1)(0, 0), kFit);
  for (const auto& p : course->points) EXPECT_NEAR(p.held, E_of(G1)(0, 0), kFit);
  model.material_angle = 45;  // neither surface
  EXPECT_FALSE(test_surface_points(model, data).has_value());
}

namespace {
// A wale-pulled test (material_angle 0: course along x) whose field is homogeneous: εC held at `held`,
// εW = 0.1 k at step k = 1…5 (Green–Lagrange, exact), a single guide value without a setting.
std::pair<fem::TestModel, TestData> held_and_pulled(const std::string& name, double held) {
  fem::TestModel model;
  fem::MeshOptions mo;
  mo.width = 50, mo.height = 50, mo.nx = 2, mo.ny = 2;
  model.mesh = fem::make_quarter_mesh(mo);
  model.name = name;
  model.guide = {4.0};
  TestData data;
  data.name = name;
  data.points.resize(2, 4);
  data.points << 1, 10, 3, 20, 2, 4, 15, 30;
  data.point_ids = {1, 2, 3, 4};
  const double gC = std::sqrt(1 + 2 * held) - 1;
  data.u.resize(5, 4), data.v.resize(5, 4);
  for (int k = 0; k < 5; ++k) {
    const double gW = std::sqrt(1 + 2 * 0.1 * (k + 1)) - 1;
    model.loads.push_back(k + 1.0), data.loads.push_back(k + 1.0), data.edge_force.push_back(10.0 * (k + 1));
    for (int i = 0; i < 4; ++i) data.u(k, i) = gC * data.points(0, i), data.v(k, i) = gW * data.points(1, i);
  }
  return {model, data};
}
}  // namespace

// The restriction keeps the test whose held εC lies in the domain, cut at the last step whose pulled
// εW is within the domain's maximum, and leaves out the one held outside (paper §4.3.2).
TEST(RestrictToDomain, KeepsTheTestsHeldInsideCutAtThePulledMaximum) {
  constexpr double kFit = 1e-12;  // exact homogeneous fields
  auto [m1, d1] = held_and_pulled("inside", 0.6);
  auto [m2, d2] = held_and_pulled("outside", 0.2);
  Experiment e;
  e.tests = {d1, d2};
  StrainDomain domain;
  domain.eC_min = 0.5, domain.eC_max = 1.1, domain.eW_min = 0.1, domain.eW_max = 0.35;
  const Restriction r = restrict_to_domain({m1, m2}, e, domain);
  ASSERT_EQ(r.tests.size(), 2u);
  EXPECT_EQ(r.tests[0].kept, 3);  // εW 0.1, 0.2, 0.3 ≤ 0.35 < 0.4
  EXPECT_EQ(r.tests[0].steps, 5);
  EXPECT_NEAR(r.tests[0].held, 0.6, kFit);
  EXPECT_NEAR(r.tests[0].pulled, 0.3, kFit);
  EXPECT_EQ(r.tests[1].kept, 0);
  EXPECT_NEAR(r.tests[1].held, 0.2, kFit);
  ASSERT_EQ(r.models.size(), 1u);
  ASSERT_EQ(r.experiment.tests.size(), 1u);
  const TestData& d = r.experiment.tests[0];
  EXPECT_EQ(d.name, "inside");
  EXPECT_EQ(d.steps(), 3);
  EXPECT_EQ(d.edge_force.size(), 3u);
  EXPECT_EQ(d.u.rows(), 3);
  EXPECT_EQ(d.v.rows(), 3);
  EXPECT_NO_THROW(d.validate());
  EXPECT_EQ(r.models[0].loads, (std::vector<double>{1, 2, 3}));
  // The guide moved with the load (4 · load / 5): the cut keeps its path, not 4 · load / 3.
  ASSERT_EQ(r.models[0].guide.size(), 3u);
  EXPECT_NEAR(r.models[0].guide[2], 4.0 * 3 / 5, kFit);

  // A domain that keeps nothing, and a test without centre strains, are errors naming data.domain.
  domain.eC_min = 2, domain.eC_max = 3;
  try {
    (void)restrict_to_domain({m1, m2}, e, domain);
    FAIL() << "no error";
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().key, "data.domain");
  }
  m1.material_angle = 45;
  EXPECT_THROW((void)restrict_to_domain({m1, m2}, e, domain), InputError);
}
