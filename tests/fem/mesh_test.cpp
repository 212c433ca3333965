#include "tricot/fem/mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

constexpr double kExact = 1e-12;  // node coordinates are sums of a few doubles

MeshOptions options(ElementType type, int nx, int ny, double grading = 1) {
  MeshOptions o;
  o.width = 10, o.height = 30, o.nx = nx, o.ny = ny, o.type = type, o.grading = grading;
  return o;
}

TEST(QuarterMesh, Q4HasAGridOfNodesAndSortedEdges) {
  const Mesh m = make_quarter_mesh(options(ElementType::Q4, 3, 5));
  EXPECT_EQ(m.nodes(), 4 * 6);
  EXPECT_EQ(m.elements(), 15);
  EXPECT_EQ(m.dofs(), 48);
  ASSERT_EQ(m.left.size(), 6u);
  ASSERT_EQ(m.right.size(), 6u);
  ASSERT_EQ(m.bottom.size(), 4u);
  ASSERT_EQ(m.top.size(), 4u);
  for (size_t k = 0; k < m.left.size(); ++k) {
    EXPECT_NEAR(m.X(0, m.left[k]), 0, kExact);
    EXPECT_NEAR(m.X(0, m.right[k]), 10, kExact);
    if (k > 0) {
      EXPECT_GT(m.X(1, m.left[k]), m.X(1, m.left[k - 1]));
    }
  }
  for (size_t k = 0; k < m.top.size(); ++k) {
    EXPECT_NEAR(m.X(1, m.bottom[k]), 0, kExact);
    EXPECT_NEAR(m.X(1, m.top[k]), 30, kExact);
    if (k > 0) {
      EXPECT_GT(m.X(0, m.top[k]), m.X(0, m.top[k - 1]));
    }
  }
}

TEST(QuarterMesh, Q8HasSerendipityNodesWithMidSidesHalfWay) {
  const int nx = 3, ny = 4;
  const Mesh m = make_quarter_mesh(options(ElementType::Q8, nx, ny, 0.25));
  EXPECT_EQ(m.nodes(), (2 * nx + 1) * (2 * ny + 1) - nx * ny);
  EXPECT_EQ(m.left.size(), 2u * ny + 1);
  EXPECT_EQ(m.top.size(), 2u * nx + 1);
  for (const auto& c : m.connectivity)
    for (int s = 0; s < 4; ++s)  // mid-side 4+s between corners s and s+1
      EXPECT_LT((m.X.col(c[4 + s]) - 0.5 * (m.X.col(c[s]) + m.X.col(c[(s + 1) % 4]))).norm(), kExact);
}

TEST(QuarterMesh, CornersRunCounterClockwise) {
  const Mesh m = make_quarter_mesh(options(ElementType::Q8, 2, 2));
  for (const auto& c : m.connectivity) {
    const Vec2 a = m.X.col(c[1]) - m.X.col(c[0]), b = m.X.col(c[3]) - m.X.col(c[0]);
    EXPECT_GT(a(0) * b(1) - a(1) * b(0), 0);
  }
}

TEST(QuarterMesh, GradingSetsTheRatioOfFirstToLastElementHeight) {
  for (ElementType t : {ElementType::Q4, ElementType::Q8}) {
    const Mesh m = make_quarter_mesh(options(t, 2, 6, 4.0));
    const auto& c0 = m.connectivity.front();
    const auto& cl = m.connectivity.back();
    const double first = m.X(1, c0[3]) - m.X(1, c0[0]), last = m.X(1, cl[3]) - m.X(1, cl[0]);
    EXPECT_NEAR(first / last, 4.0, 1e-12);
    EXPECT_NEAR(m.X(1, m.top[0]), 30, kExact);
  }
}

TEST(QuarterMesh, GradingXSetsTheRatioOfFirstToLastElementWidth) {
  for (ElementType t : {ElementType::Q4, ElementType::Q8}) {
    MeshOptions o = options(t, 5, 2);
    o.grading_x = 0.5;  // refined toward the side edge
    const Mesh m = make_quarter_mesh(o);
    const auto& c0 = m.connectivity.front();
    const auto& cl = m.connectivity[4];  // last of the first row
    const double first = m.X(0, c0[1]) - m.X(0, c0[0]), last = m.X(0, cl[1]) - m.X(0, cl[0]);
    EXPECT_NEAR(first / last, 0.5, 1e-12);
    EXPECT_NEAR(m.X(0, m.right[0]), 10, kExact);
  }
  MeshOptions o;
  o.grading_x = -1;
  EXPECT_THROW(o.validate(), InputError);
}

TEST(MeshOptions, BadValuesThrowNamingTheKey) {
  auto key_of = [](MeshOptions o) -> std::string {
    try {
      o.validate();
    } catch (const InputError& e) {
      return e.where().key;
    }
    return "";
  };
  MeshOptions o;
  EXPECT_EQ(key_of(o), "");
  o = {}, o.width = -1;
  EXPECT_EQ(key_of(o), "mesh.width");
  o = {}, o.height = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(key_of(o), "mesh.height");
  o = {}, o.nx = 0;
  EXPECT_EQ(key_of(o), "mesh.nx");
  o = {}, o.ny = 2001;
  EXPECT_EQ(key_of(o), "mesh.ny");
  o = {}, o.grading = 0;
  EXPECT_EQ(key_of(o), "mesh.grading");
  o = {}, o.width = -1;
  EXPECT_THROW(make_quarter_mesh(o), InputError);
}

TEST(ElementType, NamesAndNodeCounts) {
  EXPECT_STREQ(to_string(ElementType::Q4), "Q4");
  EXPECT_STREQ(to_string(ElementType::Q8), "Q8");
  EXPECT_EQ(nodes_per_element(ElementType::Q4), 4);
  EXPECT_EQ(nodes_per_element(ElementType::Q8), 8);
}

}  // namespace
}  // namespace tricot::fem
