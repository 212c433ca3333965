#include "tricot/fem/locate.hpp"

#include <gtest/gtest.h>

#include <random>

#include "tricot/fem/element.hpp"

namespace tricot::fem {
namespace {

// Newton stops at |Δξ| < 1e-13; a few ulps of map evaluation remain.
constexpr double kXiRoundTrip = 1e-10;
// A linear field is reproduced exactly by Q4 and Q8; only rounding remains.
constexpr double kLinearExact = 1e-11;

Vec2 map(const Mesh& m, const Eigen::Matrix2Xd& x, int e, const Vec2& xi) {
  const ShapeValues s = shape(m.type, xi);
  Vec2 p = Vec2::Zero();
  for (int a = 0; a < nodes_per_element(m.type); ++a) p += s.N(a) * x.col(m.connectivity[e][a]);
  return p;
}

Mesh one_element(ElementType type, const std::vector<Vec2>& nodes) {
  Mesh m;
  m.type = type;
  m.X.resize(2, static_cast<int>(nodes.size()));
  std::array<int, 8> c;
  c.fill(-1);
  for (int a = 0; a < static_cast<int>(nodes.size()); ++a) {
    m.X.col(a) = nodes[a];
    c[a] = a;
  }
  m.connectivity.push_back(c);
  return m;
}

Mesh distorted_q4() { return one_element(ElementType::Q4, {{0, 0}, {2, 0.3}, {2.5, 2}, {-0.2, 1.7}}); }

// Corners of a unit-ish square; mid-side nodes pushed out (bottom, top) and in (right): curved edges.
Mesh curved_q8() {
  return one_element(ElementType::Q8, {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, -0.3}, {1.8, 1}, {1, 2.25}, {0, 1}});
}

std::vector<Vec2> natural_points() {
  std::vector<Vec2> xi;
  for (double a : {-1.0, -0.999, -0.5, 0.0, 0.3, 0.999, 1.0})
    for (double b : {-1.0, -0.7, 0.0, 0.42, 1.0}) xi.emplace_back(a, b);
  return xi;
}

TEST(PointLocator, RoundTripsNaturalCoordinatesOnADistortedQ4) {
  const Mesh m = distorted_q4();
  const PointLocator locator(m);
  for (const Vec2& xi : natural_points()) {
    const auto at = locator.locate(map(m, m.X, 0, xi));
    ASSERT_TRUE(at) << xi.transpose();
    EXPECT_EQ(at->element, 0);
    EXPECT_LT((at->xi - xi).norm(), kXiRoundTrip) << xi.transpose();
  }
}

TEST(PointLocator, RoundTripsNaturalCoordinatesOnACurvedQ8) {
  const Mesh m = curved_q8();
  const PointLocator locator(m);
  for (const Vec2& xi : natural_points()) {
    const auto at = locator.locate(map(m, m.X, 0, xi));
    ASSERT_TRUE(at) << xi.transpose();
    EXPECT_LT((at->xi - xi).norm(), kXiRoundTrip) << xi.transpose();
  }
}

TEST(PointLocator, FindsPointsInTheBulgeOfACurvedEdgeBeyondTheCorners) {
  const Mesh m = curved_q8();
  const PointLocator locator(m);
  const Vec2 p(1, -0.2);  // below the corner line y = 0, inside the bulging bottom edge (y = −0.3 at x = 1)
  const auto at = locator.locate(p);
  ASSERT_TRUE(at);
  EXPECT_LT((map(m, m.X, 0, at->xi) - p).norm(), 1e-12);
  EXPECT_FALSE(locator.locate(Vec2(1, -0.31)));  // just outside the bulge
}

TEST(PointLocator, RejectsPointsJustOutsideAnElementEdge) {
  for (const Mesh& m : {distorted_q4(), curved_q8()}) {
    const PointLocator locator(m);
    for (const Vec2& xi : {Vec2(1 + 1e-6, 0.3), Vec2(-1 - 1e-6, -0.5), Vec2(0.2, 1 + 1e-6), Vec2(0, -1 - 1e-6)})
      EXPECT_FALSE(locator.locate(map(m, m.X, 0, xi))) << to_string(m.type) << " " << xi.transpose();
    EXPECT_FALSE(locator.locate(Vec2(50, 50)));
    EXPECT_FALSE(locator.locate(Vec2(NAN, 0)));
  }
}

TEST(PointLocator, FindsEveryPointOfAGradedQ8MeshInTheRightElement) {
  MeshOptions o;
  o.width = 30, o.height = 40, o.nx = 6, o.ny = 7, o.grading = 0.4, o.type = ElementType::Q8;
  const Mesh m = make_quarter_mesh(o);
  const PointLocator locator(m);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-0.98, 0.98);
  for (int e = 0; e < m.elements(); ++e)
    for (int k = 0; k < 5; ++k) {
      const Vec2 xi(U(rng), U(rng));
      const auto at = locator.locate(map(m, m.X, e, xi));
      ASSERT_TRUE(at);
      EXPECT_EQ(at->element, e);
      EXPECT_LT((at->xi - xi).norm(), kXiRoundTrip);
    }
}

TEST(PointLocator, LocatesInTheDeformedConfigurationWhenGivenDisplacements) {
  MeshOptions o;
  o.width = 20, o.height = 25, o.nx = 4, o.ny = 5, o.type = ElementType::Q8;
  const Mesh m = make_quarter_mesh(o);
  // A smooth large deformation: stretch along y, narrowing along x, and a quadratic bend.
  Eigen::VectorXd u(m.dofs());
  for (int n = 0; n < m.nodes(); ++n) {
    const double X = m.X(0, n), Y = m.X(1, n);
    u(2 * n) = -0.2 * X + 0.002 * Y * Y;
    u(2 * n + 1) = 0.8 * Y + 0.01 * X * X;
  }
  Eigen::Matrix2Xd x = m.X;
  for (int n = 0; n < m.nodes(); ++n) x.col(n) += u.segment<2>(2 * n);
  const PointLocator deformed(m, &u);
  const PointLocator reference(m);
  for (int e = 0; e < m.elements(); ++e) {
    const Vec2 xi(0.3, -0.6);
    const auto at = deformed.locate(map(m, x, e, xi));
    ASSERT_TRUE(at);
    EXPECT_EQ(at->element, e);
    EXPECT_LT((at->xi - xi).norm(), kXiRoundTrip);
  }
  // A point beyond the reference width but inside the stretched specimen's height.
  EXPECT_FALSE(reference.locate(Vec2(5, 40)));
  EXPECT_TRUE(deformed.locate(Vec2(5, 40)));
}

TEST(Interpolate, ReproducesALinearFieldExactlyOnQ4AndQ8) {
  for (ElementType type : {ElementType::Q4, ElementType::Q8}) {
    MeshOptions o;
    o.width = 10, o.height = 12, o.nx = 3, o.ny = 4, o.grading = 0.5, o.type = type;
    const Mesh m = make_quarter_mesh(o);
    Mat2 B;
    B << 0.3, -0.2, 0.15, 0.7;
    const Vec2 a(1.5, -2);
    Eigen::VectorXd v(m.dofs());
    for (int n = 0; n < m.nodes(); ++n) v.segment<2>(2 * n) = a + B * m.X.col(n);
    const PointLocator locator(m);
    for (const Vec2& p : {Vec2(0.1, 0.1), Vec2(3.3, 7.7), Vec2(9.99, 12), Vec2(5, 0)}) {
      const auto at = locator.locate(p);
      ASSERT_TRUE(at) << p.transpose();
      const Vec2 exact = a + B * p;
      EXPECT_LT((interpolate(m, *at, v) - exact).norm(), kLinearExact);
      const Interpolant I = interpolant(m, *at);
      Vec2 through = Vec2::Zero();
      for (size_t k = 0; k < I.w.size(); ++k) through += I.w[k] * Vec2(v(I.dofs_x[k]), v(I.dofs_y[k]));
      EXPECT_LT((through - exact).norm(), kLinearExact);
      EXPECT_NEAR(shape_functions(type, at->xi).sum(), 1.0, 1e-14);
    }
  }
}

}  // namespace
}  // namespace tricot::fem
