#include "tricot/fem/element.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "testing/fd_check.hpp"
#include "testing_law.hpp"
#include "tricot/fem/mooney_rivlin.hpp"

namespace tricot::fem {
namespace {

constexpr double kRoundOff = 1e-13;  // sums of a few O(1) products
constexpr double kFd = 1e-6;         // central differences of smooth functions, h = 1e-6
constexpr double kNoSaturation = std::numeric_limits<double>::infinity();

// One element of the given type on a distorted quadrilateral, or a triangle of its first three
// corners (quadratic types: mid-sides moved off-centre, so the sides are curved).
Mesh distorted_element(ElementType type) {
  Mesh m;
  m.type = type;
  const int n = nodes_per_element(type), k = corners(type);
  m.X.resize(2, n);
  const Vec2 corner[4] = {{0.1, -0.2}, {2.3, 0.1}, {2.0, 1.9}, {-0.3, 1.4}};
  std::array<int, 8> c{};
  c.fill(-1);
  for (int a = 0; a < k; ++a) m.X.col(a) = corner[a], c[a] = a;
  if (n > k) {
    const Vec2 bump[4] = {{0.05, -0.1}, {0.12, 0.03}, {-0.04, 0.08}, {-0.1, -0.05}};
    for (int s = 0; s < k; ++s) {
      m.X.col(k + s) = 0.5 * (m.X.col(s) + m.X.col((s + 1) % k)) + bump[s];
      c[k + s] = k + s;
    }
  }
  m.connectivity = {c};
  return m;
}

// The element's nodes in natural coordinates (Mesh's node order).
std::vector<Vec2> natural_nodes(ElementType type) {
  if (is_triangle(type)) return {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
  return {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}};
}

// Stretched, sheared and rotated by 30°, plus a smooth non-affine part.
Eigen::VectorXd deformed_state(const Mesh& m) {
  const double t = std::numbers::pi / 6;
  Mat2 R;
  R << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  Mat2 U;
  U << 1.4, 0.15, 0.15, 0.8;
  Eigen::VectorXd u(m.dofs());
  for (int a = 0; a < m.nodes(); ++a) {
    const Vec2 X = m.X.col(a);
    u.segment<2>(2 * a) = R * U * X - X + 0.05 * Vec2(std::sin(X(1)), X(0) * X(0));
  }
  return u;
}

// Measured errors go to the gtest XML/JSON report (docs/validation.md reads them there).
void record(const std::string& key, double value) {
  std::ostringstream o;
  o.precision(3);
  o << value;
  ::testing::Test::RecordProperty(key, o.str());
}

ElementResponse respond(const Mesh& m, const Eigen::VectorXd& u, const Law& law, bool sensitivities = false) {
  LawRequest req;
  req.sensitivities = sensitivities;
  LawOutput scratch;
  ElementResponse r;
  const ElementStatus s =
      element_response(element_geometry(m, 0), element_displacements(m, 0, u), law, material_axes(25), req, scratch, r);
  EXPECT_EQ(s, ElementStatus::ok);
  return r;
}

class ElementTypes : public ::testing::TestWithParam<ElementType> {};

TEST_P(ElementTypes, ShapeFunctionsArePartitionOfUnityAndInterpolateNodes) {
  const ElementType type = GetParam();
  const int n = nodes_per_element(type);
  const std::vector<Vec2> nodes = natural_nodes(type);
  for (int a = 0; a < n; ++a) {
    const ShapeValues s = shape(type, nodes[a]);
    for (int b = 0; b < n; ++b) EXPECT_NEAR(s.N(b), a == b ? 1.0 : 0.0, kRoundOff);
  }
  const ShapeValues s = shape(type, is_triangle(type) ? Vec2(0.3, 0.45) : Vec2(0.3, -0.7));
  EXPECT_NEAR(s.N.sum(), 1, kRoundOff);
  EXPECT_NEAR(s.dN_dxi.col(0).sum(), 0, kRoundOff);
  EXPECT_NEAR(s.dN_dxi.col(1).sum(), 0, kRoundOff);
}

TEST_P(ElementTypes, ShapeDerivativesMatchFiniteDifferences) {
  const ElementType type = GetParam();
  const int n = nodes_per_element(type);
  auto N = [&](const Eigen::VectorXd& xi) -> Eigen::VectorXd { return shape(type, xi).N.head(n); };
  const Eigen::VectorXd xi = is_triangle(type) ? Vec2(0.31, 0.22) : Vec2(0.31, -0.62);
  EXPECT_TRUE(test::JacobianMatches(N, xi, shape(type, xi).dN_dxi.topRows(n), kFd));
}

TEST_P(ElementTypes, QuadratureIntegratesTheCurvedAreaExactly) {
  const Mesh m = distorted_element(GetParam());
  const ElementGeometry g = element_geometry(m, 0);
  double area = 0;
  for (int q = 0; q < g.points; ++q) area += g.dA0[q];
  // Corner polygon (shoelace) plus, for Q8 and T6, the parabolic bulges of the curved sides
  // (2/3 · chord × offset).
  double expected = 0;
  const int k = corners(GetParam());
  for (int s = 0; s < k; ++s) {
    const Vec2 a = m.X.col(s), b = m.X.col((s + 1) % k);
    expected += 0.5 * (a(0) * b(1) - a(1) * b(0));
    if (nodes_per_element(GetParam()) > k) {
      const Vec2 d = m.X.col(k + s) - 0.5 * (a + b), chord = b - a;
      expected += 2.0 / 3.0 * (chord(0) * d(1) - chord(1) * d(0)) * -1;
    }
  }
  EXPECT_NEAR(area, expected, 1e-12);
}

TEST_P(ElementTypes, TangentMatchesFiniteDifferencesOfTheInternalForceAndIsSymmetric) {
  const Mesh m = distorted_element(GetParam());
  const int D = m.dofs();
  const test::TestingLaw law(1.3, 2.1, 0.7);
  const Eigen::VectorXd u = deformed_state(m);
  auto force = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return respond(m, v, law).f.head(D); };
  const ElementResponse r = respond(m, u, law);
  record("element_tangent_fd_error", test::jacobian_error(force, u, r.K.topLeftCorner(D, D)));
  EXPECT_TRUE(test::JacobianMatches(force, u, r.K.topLeftCorner(D, D), kFd));
  EXPECT_TRUE(r.symmetric_tangent);
  EXPECT_LT((r.K.topLeftCorner(D, D) - r.K.topLeftCorner(D, D).transpose()).cwiseAbs().maxCoeff(),
            kRoundOff * r.K.cwiseAbs().maxCoeff());
}

TEST_P(ElementTypes, MooneyRivlinTangentMatchesFiniteDifferencesOfTheForce) {
  const Mesh m = distorted_element(GetParam());
  const int D = m.dofs();
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  const Eigen::VectorXd u = deformed_state(m);
  auto force = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return respond(m, v, law).f.head(D); };
  record("element_tangent_fd_error_mooney", test::jacobian_error(force, u, respond(m, u, law).K.topLeftCorner(D, D)));
  EXPECT_TRUE(test::JacobianMatches(force, u, respond(m, u, law).K.topLeftCorner(D, D), kFd));
}

TEST_P(ElementTypes, CoefficientSensitivityMatchesFiniteDifferences) {
  const Mesh m = distorted_element(GetParam());
  const int D = m.dofs();
  const Eigen::VectorXd u = deformed_state(m);
  for (double saturation : {kNoSaturation, 3.0}) {
    test::TestingLaw law(1.3, 2.1, 0.7, saturation);
    const Eigen::VectorXd c = law.coefficients();
    auto force = [&](const Eigen::VectorXd& cc) -> Eigen::VectorXd {
      test::TestingLaw l = law;
      l.set_coefficients(cc);
      return respond(m, u, l).f.head(D);
    };
    record(std::isfinite(saturation) ? "element_df_dc_fd_error_softening" : "element_df_dc_fd_error",
           test::jacobian_error(force, c, respond(m, u, law, true).df_dc));
    EXPECT_TRUE(test::JacobianMatches(force, c, respond(m, u, law, true).df_dc, kFd)) << "saturation " << saturation;
  }
}

TEST_P(ElementTypes, RigidRotationKeepsTheStressInvariants) {
  // Rotating every deformed node about the origin by 70°: F → R F, so σ → R σ Rᵀ (same invariants),
  // and the internal force rotates with the nodes.
  const Mesh m = distorted_element(GetParam());
  const test::TestingLaw law(1.3, 2.1, 0.7);
  const Eigen::VectorXd u = deformed_state(m);
  const double t = 70 * std::numbers::pi / 180;
  Mat2 R;
  R << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  Eigen::VectorXd ur(u.size());
  for (int a = 0; a < m.nodes(); ++a) {
    const Vec2 X = m.X.col(a);
    ur.segment<2>(2 * a) = R * (X + u.segment<2>(2 * a)) - X;
  }
  const Vec2 xi = is_triangle(GetParam()) ? Vec2(0.2, 0.4) : Vec2(0.2, -0.4);
  const Mat2 F = deformation_gradient(m, 0, xi, u), Fr = deformation_gradient(m, 0, xi, ur);
  EXPECT_LT((Fr - R * F).norm(), kRoundOff);
  LawInput in;
  in.Q = material_axes(25);
  LawOutput o, orot;
  in.F = F;
  law.evaluate(in, {}, o);
  in.F = Fr;
  law.evaluate(in, {}, orot);
  const Mat2 s = Law::cauchy(F, o.P), sr = Law::cauchy(Fr, orot.P);
  EXPECT_NEAR(sr.trace(), s.trace(), kRoundOff * s.norm());
  EXPECT_NEAR(sr.determinant(), s.determinant(), kRoundOff * s.squaredNorm());
  const ElementResponse r = respond(m, u, law), rr = respond(m, ur, law);
  for (int a = 0; a < m.nodes(); ++a)
    EXPECT_LT((rr.f.segment<2>(2 * a) - R * r.f.segment<2>(2 * a)).norm(), kRoundOff * r.f.norm());
}

TEST_P(ElementTypes, InvertedStateIsReported) {
  const Mesh m = distorted_element(GetParam());
  Eigen::VectorXd u(m.dofs());
  for (int a = 0; a < m.nodes(); ++a) u.segment<2>(2 * a) = Vec2(-2 * m.X(0, a), 0);  // x → −x: det F = −1
  LawOutput scratch;
  ElementResponse r;
  const test::TestingLaw law;
  EXPECT_EQ(
      element_response(element_geometry(m, 0), element_displacements(m, 0, u), law, Mat2::Identity(), {}, scratch, r),
      ElementStatus::inverted);
  EXPECT_LT(r.min_detF, 0);
}

INSTANTIATE_TEST_SUITE_P(Q4AndQ8, ElementTypes, ::testing::Values(ElementType::Q4, ElementType::Q8),
                         [](const auto& info) { return std::string(to_string(info.param)); });
INSTANTIATE_TEST_SUITE_P(T3AndT6, ElementTypes, ::testing::Values(ElementType::T3, ElementType::T6),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST(MaterialAxes, CourseAndWaleAreTheAngleAndItsNormal) {
  const Mat2 Q = material_axes(30);
  EXPECT_NEAR(Q(0, 0), std::sqrt(3.0) / 2, kRoundOff);
  EXPECT_NEAR(Q(1, 0), 0.5, kRoundOff);
  EXPECT_NEAR(Q(0, 1), -0.5, kRoundOff);
  EXPECT_NEAR(Q(1, 1), std::sqrt(3.0) / 2, kRoundOff);
}

TEST(TestingLaw, TangentAndSensitivitiesMatchFiniteDifferences) {
  // The test law itself must be right before it checks the elements.
  for (double saturation : {kNoSaturation, 2.0}) {
    const test::TestingLaw law(1.3, 2.1, 0.7, saturation);
    LawInput in;
    in.Q = material_axes(40);
    Mat2 F;
    F << 1.3, 0.2, -0.1, 0.9;
    auto P = [&](const Eigen::VectorXd& f) -> Eigen::VectorXd {
      LawInput i = in;
      i.F = unflatten(f);
      LawOutput o;
      law.evaluate(i, {}, o);
      return flatten(o.P);
    };
    in.F = F;
    LawOutput o;
    law.evaluate(in, {true, true}, o);
    EXPECT_TRUE(test::JacobianMatches(P, flatten(F), o.A, kFd));
  }
}

}  // namespace
}  // namespace tricot::fem
