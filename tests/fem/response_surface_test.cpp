#include "tricot/fem/response_surface.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "testing/fd_check.hpp"
#include "testing/law_eval.hpp"
#include "testing/record.hpp"
#include "testing/states.hpp"
#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::fem;
using tricot::test::JacobianMatches;
using tricot::test::P_of;
using tricot::test::record_scientific;
using tricot::test::rot;

namespace {

/// Central differences (h = 1e-6) of these smooth maps are exact to ~1e-9 relative; a wrong term is O(1).
constexpr double kFdTol = 1e-7;
/// At rest and at a small strain the central differences straddle ε = 0, where the compression
/// branch (docs/theory/fabric.md §3.1) is C¹ but its curvature jumps: error O(h |a_2| / a_1) ≈ 1e-6.
constexpr double kFdKinkTol = 1e-5;
/// Identities that hold exactly in real arithmetic, checked to a few ulps of the O(1) forces.
constexpr double kRoundOff = 1e-13;

/// Coefficients of the paper14 preset with a knit-like shape [N/mm] (course stiff and J-shaped, wale soft).
Eigen::VectorXd paper14_coefficients() {
  Eigen::VectorXd c(14);
  c << 0.25, -0.10, 0.20, -0.08, 0.03, 0.004,  // a1..a6
      0.03, -0.01,                             // b1, b2
      0.06, 0.02, -0.01, 0.015,                // c1..c4
      0.02, 0.01;                              // d1, d2
  return c;
}

ResponseSurface paper14() {
  ResponseSurface law = ResponseSurface::preset("paper14", 0.01);
  law.set_coefficients(paper14_coefficients());
  return law;
}

using Compression = ResponseSurface::Compression;

/// x^n, or its compression branch (docs/theory/fabric.md §3.1 [choice]): for x < 0, 0 for n ≥ 2, and
/// x^1 = x (linear, or the other force's strain) or the Euler–Almansi strain (1 − λ⁻²)/2 with
/// λ² = 1 + 2x (almansi, the force's own strain).
double power(double x, int n, Compression mode, bool own) {
  if (x >= 0 || mode == Compression::polynomial) return std::pow(x, n);
  if (n >= 2) return 0.0;
  if (mode == Compression::linear || !own) return x;
  const double lambda2 = 1 + 2 * x;
  return 0.5 * (1 - 1 / lambda2);
}

/// docs/theory.md §5 written out independently of the implementation.
Vec2 paper14_forces(double eC, double eW, Compression mode = Compression::almansi) {
  const Eigen::VectorXd c = paper14_coefficients();
  double FC = 0, FW = 0;
  for (int i = 1; i <= 6; ++i) FC += c(i - 1) * power(eC, i, mode, true);
  for (int j = 1; j <= 2; ++j) FC += c(5 + j) * power(eW, j, mode, false);
  for (int i = 1; i <= 4; ++i) FW += c(7 + i) * power(eW, i, mode, true);
  for (int j = 1; j <= 2; ++j) FW += c(11 + j) * power(eC, j, mode, false);
  return {FC, FW};
}

/// A general surface with cross terms (combined-stretch stiffening).
ResponseSurface general() {
  Eigen::VectorXd c(6);
  c << 0.3, 0.05, 0.04, 0.07, 0.02, -0.03;
  return ResponseSurface({{1, 0}, {3, 0}, {1, 2}}, {{0, 1}, {2, 1}, {1, 0}}, 0.02, c);
}

std::vector<test::State> states() {
  Mat2 combined;
  combined << 1.6, 0.3, -0.2, 1.25;
  return test::orthotropic_law_states({"large stretch", Vec2(1.8, 1.3).asDiagonal()}, combined);
}

}  // namespace

TEST(ResponseSurface, TangentMatchesFiniteDifferencesFromIdentityToLargeRotations) {
  double worst = 0;
  for (const ResponseSurface& law : {paper14(), general()}) {
    for (const Mat2& Q : {Mat2(Mat2::Identity()), rot(30)}) {
      for (const auto& s : states()) {
        LawOutput out;
        law.evaluate({s.F, Q}, {true, false}, out);
        auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return flatten(P_of(law, unflatten(Vec4(x)), Q)); };
        const bool at_kink = s.name == "identity" || s.name == "small strain";
        EXPECT_TRUE(JacobianMatches(P, flatten(s.F), out.A, at_kink ? kFdKinkTol : kFdTol)) << s.name;
        if (!at_kink) worst = std::max(worst, tricot::test::jacobian_error(P, flatten(s.F), out.A));
      }
    }
  }
  record_scientific("max_tangent_fd_rel_error", worst);
}

TEST(ResponseSurface, CoefficientSensitivitiesAreExactAndSumToP) {
  double worst = 0;
  for (const ResponseSurface& law : {paper14(), general()}) {
    const Mat2 Q = rot(-40);
    for (const auto& s : states()) {
      if (s.name == "identity") continue;  // every basis stress vanishes at rest
      LawOutput out;
      law.evaluate({s.F, Q}, {false, true}, out);
      const Eigen::Index n = law.coefficients().size();
      ASSERT_EQ(out.dP_dc.size(), static_cast<std::size_t>(n));
      Eigen::MatrixXd J(4, n);
      for (Eigen::Index k = 0; k < n; ++k) J.col(k) = flatten(out.dP_dc[k]);
      auto P = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
        ResponseSurface l = law;
        l.set_coefficients(c);
        return flatten(P_of(l, s.F, Q));
      };
      EXPECT_TRUE(JacobianMatches(P, law.coefficients(), J, kFdTol)) << s.name;
      worst = std::max(worst, tricot::test::jacobian_error(P, law.coefficients(), J));
      // P = Σ c_k ∂P/∂c_k + the G_s shear part, which no coefficient scales.
      ResponseSurface zero = law;
      zero.set_coefficients(Eigen::VectorXd::Zero(n));
      const Vec4 shear_part = flatten(P_of(zero, s.F, Q));
      EXPECT_LT((J * law.coefficients() + shear_part - flatten(P_of(law, s.F, Q))).norm(), kRoundOff) << s.name;
    }
  }
  record_scientific("max_dP_dc_fd_rel_error", worst);
}

TEST(ResponseSurface, HomogeneousBiaxialForcesAreThePolynomialAtTheImposedStrains) {
  const ResponseSurface law = paper14();
  double worst = 0;
  for (double l1 : {1.0, 1.2, 1.414, 1.7}) {
    for (double l2 : {0.9, 1.0, 1.1, 1.3}) {
      const double e1 = 0.5 * (l1 * l1 - 1), e2 = 0.5 * (l2 * l2 - 1);
      const Mat2 F = Vec2(l1, l2).asDiagonal();
      // Loaded along course (course = x): P = diag(F_C(ε1, ε2), F_W(ε1, ε2)).
      const Vec2 f = paper14_forces(e1, e2);
      const Mat2 P = P_of(law, F, Mat2::Identity());
      EXPECT_NEAR(P(0, 0), f(0), kRoundOff) << l1 << " " << l2;
      EXPECT_NEAR(P(1, 1), f(1), kRoundOff) << l1 << " " << l2;
      EXPECT_EQ(P(0, 1), 0.0);
      EXPECT_EQ(P(1, 0), 0.0);
      // Loaded along wale (course = y): P11 = F_W(εC = ε2, εW = ε1), P22 = F_C(ε2, ε1).
      const Vec2 g = paper14_forces(e2, e1);
      const Mat2 Pw = P_of(law, F, rot(90));
      EXPECT_NEAR(Pw(0, 0), g(1), kRoundOff) << l1 << " " << l2;
      EXPECT_NEAR(Pw(1, 1), g(0), kRoundOff) << l1 << " " << l2;
      worst = std::max({worst, std::abs(P(0, 0) - f(0)), std::abs(P(1, 1) - f(1)), std::abs(Pw(0, 0) - g(1)),
                        std::abs(Pw(1, 1) - g(0))});
    }
  }
  record_scientific("biaxial_max_abs_error_N_per_mm", worst);
}

TEST(ResponseSurface, RigidRotationRotatesPAndLeavesTheLocalForcesUnchanged) {
  Mat2 F;
  F << 1.5, 0.25, -0.1, 1.2;
  const Mat2 Q = rot(25);
  double worst = 0;
  for (const ResponseSurface& law : {paper14(), general()}) {
    for (double deg : {37.0, 90.0, 180.0, -100.0}) {
      const Mat2 Q0 = rot(deg);
      const double eP = (P_of(law, Q0 * F, Q) - Q0 * P_of(law, F, Q)).norm();
      const double eT = (law.material_frame_stress({Q0 * F, Q}) - law.material_frame_stress({F, Q})).norm();
      EXPECT_LT(eP, kRoundOff) << deg;
      EXPECT_LT(eT, kRoundOff) << deg;
      worst = std::max({worst, eP / P_of(law, F, Q).norm(), eT / law.material_frame_stress({F, Q}).norm()});
    }
    EXPECT_LT(P_of(law, rot(140), Q).norm(), kRoundOff);  // rigid rotation alone: no force
  }
  record_scientific("rotation_max_rel_error", worst);
}

TEST(ResponseSurface, NinetyDegreeMaterialAngleWithSwappedCoefficientsGivesIdenticalP) {
  // paper24 is symmetric in structure: swapping course and wale swaps (a, b) with (c, d).
  ResponseSurface law = ResponseSurface::preset("paper24", 0.01);
  Eigen::VectorXd c(24), swapped(24);
  for (int i = 0; i < 24; ++i) c(i) = 0.05 / (1 + i) * (i % 3 == 2 ? -1 : 1);
  swapped << c.segment(12, 6), c.segment(18, 6), c.segment(0, 6), c.segment(6, 6);
  law.set_coefficients(c);
  ResponseSurface law_swapped = law;
  law_swapped.set_coefficients(swapped);
  // General surface: exchange the force lists and every exponent pair (p, q) -> (q, p).
  const ResponseSurface g = general();
  std::vector<Monomial> course, wale;
  for (const Monomial& m : g.wale_monomials()) course.push_back({m.q, m.p});
  for (const Monomial& m : g.course_monomials()) wale.push_back({m.q, m.p});
  const Eigen::VectorXd gc = g.coefficients();
  const Eigen::Index nc = static_cast<Eigen::Index>(g.course_monomials().size());
  Eigen::VectorXd gs(gc.size());
  gs << gc.tail(gc.size() - nc), gc.head(nc);
  const ResponseSurface g_swapped(course, wale, g.shear_stiffness(), gs);

  double worst = 0;
  for (const auto& s : states()) {
    for (const Mat2& Q : {Mat2(Mat2::Identity()), rot(20)}) {
      const double e1 = (P_of(law, s.F, Q * rot(90)) - P_of(law_swapped, s.F, Q)).norm();
      const double e2 = (P_of(g, s.F, Q * rot(90)) - P_of(g_swapped, s.F, Q)).norm();
      EXPECT_LT(e1, kRoundOff) << s.name;
      EXPECT_LT(e2, kRoundOff) << s.name;
      if (s.name != "identity")
        worst = std::max({worst, e1 / P_of(law_swapped, s.F, Q).norm(), e2 / P_of(g_swapped, s.F, Q).norm()});
    }
    // Turning the whole test by 90° (material and deformation) turns P with it.
    const Mat2 Z = rot(90);
    EXPECT_LT((P_of(law, Z * s.F * Z.transpose(), Z) - Z * P_of(law, s.F, Mat2::Identity()) * Z.transpose()).norm(),
              kRoundOff)
        << s.name;
  }
  record_scientific("swap_max_rel_error", worst);
}

TEST(ResponseSurface, SmallShearIsCarriedByTheFixedShearStiffness) {
  const ResponseSurface law = paper14();
  const double gamma = 0.3;
  EXPECT_NEAR(law.material_frame_stress({test::shear(gamma), Mat2::Identity()})(0, 1), law.shear_stiffness() * gamma,
              kRoundOff);
}

TEST(ResponseSurface, PresetsNameTheirCoefficientsAsInTheTheory) {
  const std::vector<std::string> p14 = {"a1", "a2", "a3", "a4", "a5", "a6", "b1",
                                        "b2", "c1", "c2", "c3", "c4", "d1", "d2"};
  EXPECT_EQ(ResponseSurface::preset("paper14").coefficient_names(), p14);
  const ResponseSurface p24 = ResponseSurface::preset("paper24");
  ASSERT_EQ(p24.coefficient_names().size(), 24u);
  EXPECT_EQ(p24.coefficient_names()[6], "b1");
  EXPECT_EQ(p24.coefficient_names()[23], "d6");
  EXPECT_EQ(general().coefficient_names(),
            (std::vector<std::string>{"C_1_0", "C_3_0", "C_1_2", "W_0_1", "W_2_1", "W_1_0"}));
  EXPECT_EQ(ResponseSurface::preset("paper14").shear_stiffness(), ResponseSurface::kDefaultShearStiffness);
}

TEST(ResponseSurface, RejectsBadPresetsMonomialsShearStiffnessAndCoefficients) {
  EXPECT_THROW(ResponseSurface::preset("paper15"), InputError);
  EXPECT_THROW(ResponseSurface({{0, 0}}, {}, 0.01), InputError);
  EXPECT_THROW(ResponseSurface({{1, 0}, {1, 0}}, {}, 0.01), InputError);
  EXPECT_THROW(ResponseSurface({{-1, 2}}, {}, 0.01), InputError);
  EXPECT_THROW(ResponseSurface({{1, 0}}, {}, 0.0), InputError);
  ResponseSurface law = paper14();
  EXPECT_THROW(law.set_coefficients(Eigen::VectorXd::Zero(13)), InputError);
  EXPECT_THROW(law.set_coefficients(Eigen::VectorXd::Constant(14, std::nan(""))), InputError);
}

TEST(ResponseSurface, InvertedElementGivesNaN) {
  LawOutput out;
  paper14().evaluate({Vec2(-1.0, 1.0).asDiagonal(), Mat2::Identity()}, {true, true}, out);
  EXPECT_TRUE(std::isnan(out.P(0, 0)));
  EXPECT_EQ(out.dP_dc.size(), 14u);
}

TEST(ResponseSurface, CompressionKeepsOnlyTheFirstPowersAsAlmansiStrainsByDefault) {
  ResponseSurface law = paper14();
  for (double eC : {-0.38, -0.1, 0.0, 0.4})
    for (double eW : {-0.3, -0.05, 0.2}) {
      EXPECT_NEAR(law.forces(eC, eW)(0), paper14_forces(eC, eW)(0), kRoundOff) << eC << " " << eW;
      EXPECT_NEAR(law.forces(eC, eW)(1), paper14_forces(eC, eW)(1), kRoundOff) << eC << " " << eW;
    }
  // Both compressed: only a1 e(εC) + b1 εW and c1 e(εW) + d1 εC remain, e(x) = x/(1 + 2x):
  // e(−0.2) = −1/3, e(−0.1) = −0.125.
  EXPECT_NEAR(law.forces(-0.2, -0.1)(0), 0.25 * -1.0 / 3 + 0.03 * -0.1, kRoundOff);
  EXPECT_NEAR(law.forces(-0.2, -0.1)(1), 0.06 * -0.125 + 0.02 * -0.2, kRoundOff);
  // A fibre compressed toward zero length (εC → −½) needs an unbounded force: no collapse.
  EXPECT_LT(law.forces(-0.4999, 0)(0), -0.25 * 2000);
}

TEST(ResponseSurface, LinearCompressionKeepsOnlyTheLinearTermsAndPolynomialModeKeepsThePolynomial) {
  ResponseSurface law = paper14();
  law.set_compression(Compression::linear);
  for (double eC : {-0.38, -0.1, 0.0, 0.4})
    for (double eW : {-0.3, -0.05, 0.2}) {
      EXPECT_NEAR(law.forces(eC, eW)(0), paper14_forces(eC, eW, Compression::linear)(0), kRoundOff) << eC << " " << eW;
      EXPECT_NEAR(law.forces(eC, eW)(1), paper14_forces(eC, eW, Compression::linear)(1), kRoundOff) << eC << " " << eW;
    }
  // Both compressed: only a1 εC + b1 εW and c1 εW + d1 εC remain.
  EXPECT_NEAR(law.forces(-0.2, -0.1)(0), 0.25 * -0.2 + 0.03 * -0.1, kRoundOff);
  EXPECT_NEAR(law.forces(-0.2, -0.1)(1), 0.06 * -0.1 + 0.02 * -0.2, kRoundOff);
  law.set_compression(Compression::polynomial);
  EXPECT_NEAR(law.forces(-0.2, -0.1)(0), paper14_forces(-0.2, -0.1, Compression::polynomial)(0), kRoundOff);
  EXPECT_NEAR(law.forces(-0.2, -0.1)(1), paper14_forces(-0.2, -0.1, Compression::polynomial)(1), kRoundOff);
  EXPECT_NE(law.forces(-0.2, -0.1)(0), paper14_forces(-0.2, -0.1, Compression::linear)(0));
}

TEST(ResponseSurface, CompressionBranchIsC1AtZeroAndItsTangentAndSensitivitiesMatchFiniteDifferences) {
  // The slope of F along each strain is continuous at 0: one-sided differences agree with the
  // linear coefficients (the higher powers contribute O(h)).
  constexpr double h = 1e-7;
  constexpr double kOneSided = 1e-6;  // O(h) one-sided truncation with O(1) coefficients
  for (Compression mode : {Compression::almansi, Compression::linear}) {
    ResponseSurface law = paper14();
    law.set_compression(mode);
    for (double sign : {-1.0, 1.0}) {
      EXPECT_NEAR((law.forces(sign * h, 0)(0) - law.forces(0, 0)(0)) / (sign * h), 0.25, kOneSided);
      EXPECT_NEAR((law.forces(0, sign * h)(1) - law.forces(0, 0)(1)) / (sign * h), 0.06, kOneSided);
      EXPECT_NEAR((law.forces(0, sign * h)(0) - law.forces(0, 0)(0)) / (sign * h), 0.03, kOneSided);
    }
  }
  // Compressed states (the free strips of the rig): tangent and ∂P/∂c against central differences.
  Mat2 squeeze_wale, squeeze_both;
  squeeze_wale << 1.5, 0.1, -0.05, 0.62;  // εW ≈ −0.31
  squeeze_both << 0.8, 0.05, 0.02, 0.75;
  for (Compression mode : {Compression::almansi, Compression::linear})
    for (ResponseSurface l : {paper14(), general()})
      for (const Mat2& F : {squeeze_wale, squeeze_both}) {
        l.set_compression(mode);
        const Mat2 Q = rot(20);
        LawOutput out;
        l.evaluate({F, Q}, {true, true}, out);
        auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return flatten(P_of(l, unflatten(Vec4(x)), Q)); };
        EXPECT_TRUE(JacobianMatches(P, flatten(F), out.A, kFdTol));
        const Eigen::Index n = l.coefficients().size();
        Eigen::MatrixXd J(4, n);
        for (Eigen::Index k = 0; k < n; ++k) J.col(k) = flatten(out.dP_dc[k]);
        auto Pc = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
          ResponseSurface m = l;
          m.set_coefficients(c);
          return flatten(P_of(m, F, Q));
        };
        EXPECT_TRUE(JacobianMatches(Pc, l.coefficients(), J, kFdTol));
      }
}
