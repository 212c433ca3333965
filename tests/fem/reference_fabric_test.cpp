#include "tricot/fem/reference_fabric.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
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
/// Identities that hold exactly in real arithmetic, checked to a few ulps of the O(1) forces.
constexpr double kRoundOff = 1e-13;

/// docs/theory/fabric.md §4 written out independently of the implementation.
Vec2 reference_forces(const ReferenceFabricParameters& p, double eC, double eW) {
  const double LC = p.k_CL * p.s_CL * (std::exp((eC - p.eps_CL) / p.s_CL) - std::exp(-p.eps_CL / p.s_CL));
  const double LW = p.k_WL * p.s_WL * (std::exp((eW - p.eps_WL) / p.s_WL) - std::exp(-p.eps_WL / p.s_WL));
  auto jam = [&](double e) { return -p.k_J * p.s_J * (std::exp((-e - p.eps_J) / p.s_J) - std::exp(-p.eps_J / p.s_J)); };
  const double X = p.k_X / 3 * std::pow(eC + eW, 3);
  return {p.k_C * eC + LC + jam(eC) + p.k_P * eW + X, p.k_W * eW + LW + jam(eW) + p.k_P * eC + X};
}

/// Up to the locking range: λ = 1.61 is εC = 0.8 (onset), λ = 1.73 is εC = 1.0.
std::vector<test::State> states() {
  Mat2 combined;
  combined << 1.7, 0.3, -0.2, 1.3;
  Mat2 shrunk;  // a wale pull with the course narrowed into the jamming range (εC = −0.26)
  shrunk << 0.7, 0.05, 0.02, 1.5;
  auto s = test::orthotropic_law_states({"large stretch in the locking range", Vec2(1.8, 1.2).asDiagonal()}, combined);
  s.push_back({"course jammed under a wale pull", shrunk});
  return s;
}

}  // namespace

TEST(ReferenceFabric, TangentMatchesFiniteDifferencesFromIdentityToLargeRotations) {
  double worst = 0;
  const ReferenceFabric law;
  for (const Mat2& Q : {Mat2(Mat2::Identity()), rot(30), rot(90)}) {
    for (const auto& s : states()) {
      LawOutput out;
      law.evaluate({s.F, Q}, {true, false}, out);
      auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return flatten(P_of(law, unflatten(Vec4(x)), Q)); };
      EXPECT_TRUE(JacobianMatches(P, flatten(s.F), out.A, kFdTol)) << s.name;
      worst = std::max(worst, tricot::test::jacobian_error(P, flatten(s.F), out.A));
    }
  }
  record_scientific("max_tangent_fd_rel_error", worst);
}

TEST(ReferenceFabric, CoefficientSensitivitiesMatchFiniteDifferences) {
  const ReferenceFabric law;
  double worst = 0;
  const Mat2 Q = rot(-40);
  for (const auto& s : states()) {
    if (s.name == "identity") continue;  // every sensitivity vanishes at rest
    LawOutput out;
    law.evaluate({s.F, Q}, {false, true}, out);
    ASSERT_EQ(out.dP_dc.size(), 13u);
    Eigen::MatrixXd J(4, 13);
    for (int k = 0; k < 13; ++k) J.col(k) = flatten(out.dP_dc[k]);
    auto P = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
      ReferenceFabric l = law;
      l.set_coefficients(c);
      return flatten(P_of(l, s.F, Q));
    };
    EXPECT_TRUE(JacobianMatches(P, law.coefficients(), J, kFdTol)) << s.name;
    worst = std::max(worst, tricot::test::jacobian_error(P, law.coefficients(), J));
  }
  record_scientific("max_dP_dc_fd_rel_error", worst);
}

TEST(ReferenceFabric, HomogeneousBiaxialForcesAreTheDocumentedFormula) {
  const ReferenceFabric law;
  for (double l1 : {1.0, 1.3, 1.61, 1.8}) {
    for (double l2 : {0.95, 1.1, 1.3}) {
      const double e1 = 0.5 * (l1 * l1 - 1), e2 = 0.5 * (l2 * l2 - 1);
      const Vec2 f = reference_forces(law.parameters(), e1, e2);
      const Mat2 P = P_of(law, Vec2(l1, l2).asDiagonal(), Mat2::Identity());
      EXPECT_NEAR(P(0, 0), f(0), kRoundOff * (1 + std::abs(f(0))));
      EXPECT_NEAR(P(1, 1), f(1), kRoundOff * (1 + std::abs(f(1))));
      EXPECT_EQ(P(0, 1), 0.0);
      EXPECT_NEAR(law.forces(e1, e2)(0), f(0), kRoundOff * (1 + std::abs(f(0))));
    }
  }
}

TEST(ReferenceFabric, HasTheMagnitudesAndShapeOfACompressionKnit) {
  const ReferenceFabric law;
  const double FC100 = law.forces(1.0, 0.0)(0), FW100 = law.forces(0.0, 1.0)(1);
  EXPECT_GT(FC100, 0.1);  // course force per width at 100 % strain: 0.1–1 N/mm
  EXPECT_LT(FC100, 1.0);
  EXPECT_GT(FC100 / FW100, 2.5);  // wale several times softer at equal strain
  // J shape: near-linear below the locking onset, then much stiffer.
  auto slope_C = [&](double e, double eW) {
    return (law.forces(e + 1e-6, eW)(0) - law.forces(e - 1e-6, eW)(0)) / 2e-6;
  };
  auto slope_W = [&](double e) { return (law.forces(0, e + 1e-6)(1) - law.forces(0, e - 1e-6)(1)) / 2e-6; };
  EXPECT_LT(slope_C(0.5, 0) / slope_C(0.0, 0), 1.2);
  EXPECT_GT(slope_C(1.2, 0) / slope_C(0.0, 0), 3.0);
  EXPECT_GT(slope_W(1.2) / slope_W(0.0), 2.0);
  // Combined stretch stiffens the course response.
  EXPECT_GT(slope_C(0.8, 0.4), slope_C(0.8, 0.0) * 1.03);
}

namespace {

/// εC of a free-side wale pull (F_C(εC, εW) = 0), by bisection: F_C increases with εC.
double free_course_strain(const ReferenceFabric& law, double eW) {
  double lo = -0.49, hi = 0.5;
  for (int i = 0; i < 200; ++i) {
    const double m = 0.5 * (lo + hi);
    (law.forces(m, eW)(0) > 0 ? hi : lo) = m;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

// The requirement: −εC/εW of order 0.3–1 under a free-side pull, and a held width carries a
// course force of the order of the wale force. Values recorded for docs/theory/fabric.md §4.
TEST(ReferenceFabric, ShrinksAcrossAFreeSidePullAndLoadsAHeldWidth) {
  const ReferenceFabric law;
  for (double eW : {0.1, 0.3, 0.6}) {
    const double eC = free_course_strain(law, eW);
    EXPECT_NEAR(law.forces(eC, eW)(0), 0.0, kRoundOff);
    const double ratio = -eC / eW;
    EXPECT_GT(ratio, 0.3) << eW;
    EXPECT_LT(ratio, 1.0) << eW;
    tricot::test::record("shrinkage_ratio_wale_" + std::to_string(static_cast<int>(std::lround(100 * eW))), ratio);
    const Vec2 held = law.forces(0, eW);  // held width: εC = 0
    EXPECT_GT(held(0) / held(1), 0.3) << eW;
    EXPECT_LT(held(0) / held(1), 3.0) << eW;
    tricot::test::record("held_width_FC_over_FW_" + std::to_string(static_cast<int>(std::lround(100 * eW))),
                         held(0) / held(1));
  }
}

// Drucker-like stability of the strain-space response: the force Jacobian is symmetric (a potential
// in (εC, εW)) and positive definite over the campaign's range and beyond.
TEST(ReferenceFabric, ForceJacobianIsSymmetricPositiveDefiniteOverTheRange) {
  const ReferenceFabric law;
  double worst = 1e9;
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      const double eC = -0.45 + 1.65 * i / 40, eW = -0.45 + 1.45 * j / 40;
      const Mat2 A = law.force_jacobian(eC, eW);
      // Against central differences of forces(): h = 1e-6 on O(1) slopes.
      const Vec2 dC = (law.forces(eC + 1e-6, eW) - law.forces(eC - 1e-6, eW)) / 2e-6;
      const Vec2 dW = (law.forces(eC, eW + 1e-6) - law.forces(eC, eW - 1e-6)) / 2e-6;
      EXPECT_NEAR((A.col(0) - dC).norm(), 0.0, kFdTol * (1 + A.norm()));
      EXPECT_NEAR((A.col(1) - dW).norm(), 0.0, kFdTol * (1 + A.norm()));
      EXPECT_EQ(A(0, 1), A(1, 0));
      worst = std::min(worst, Eigen::SelfAdjointEigenSolver<Mat2>(A).eigenvalues()(0));
    }
  EXPECT_GT(worst, 0.0);
  record_scientific("min_force_jacobian_eigenvalue", worst);
}

TEST(ReferenceFabric, RigidRotationRotatesPAndLeavesTheLocalForcesUnchanged) {
  const ReferenceFabric law;
  Mat2 F;
  F << 1.6, 0.25, -0.1, 1.2;
  const Mat2 Q = rot(25);
  double worst = 0;
  for (double deg : {37.0, 90.0, 180.0, -100.0}) {
    const Mat2 Q0 = rot(deg);
    const double eP = (P_of(law, Q0 * F, Q) - Q0 * P_of(law, F, Q)).norm();
    const double eT = (law.material_frame_stress({Q0 * F, Q}) - law.material_frame_stress({F, Q})).norm();
    EXPECT_LT(eP, kRoundOff) << deg;
    EXPECT_LT(eT, kRoundOff) << deg;
    worst = std::max({worst, eP / P_of(law, F, Q).norm(), eT / law.material_frame_stress({F, Q}).norm()});
  }
  record_scientific("rotation_max_rel_error", worst);
}

TEST(ReferenceFabric, NinetyDegreeMaterialAngleSwapsCourseAndWale) {
  ReferenceFabricParameters p;
  ReferenceFabricParameters swapped = p;
  std::swap(swapped.k_C, swapped.k_W);
  std::swap(swapped.k_CL, swapped.k_WL);
  std::swap(swapped.eps_CL, swapped.eps_WL);
  std::swap(swapped.s_CL, swapped.s_WL);
  const ReferenceFabric law(p), law_swapped(swapped);
  double worst = 0;
  for (const auto& s : states()) {
    const double e = (P_of(law, s.F, rot(90)) - P_of(law_swapped, s.F, Mat2::Identity())).norm();
    EXPECT_LT(e, kRoundOff) << s.name;
    if (s.name != "identity") worst = std::max(worst, e / P_of(law_swapped, s.F, Mat2::Identity()).norm());
  }
  record_scientific("swap_max_rel_error", worst);
}

TEST(ReferenceFabric, RejectsOutOfRangeParameters) {
  ReferenceFabricParameters p;
  p.s_CL = 0;
  EXPECT_THROW(ReferenceFabric{p}, InputError);
  p = {};
  p.G_s = -1;
  EXPECT_THROW(ReferenceFabric{p}, InputError);
  ReferenceFabric law;
  EXPECT_THROW(law.set_coefficients(Eigen::VectorXd::Zero(3)), InputError);
  EXPECT_EQ(law.coefficient_names().size(), 13u);
  p = {};
  p.k_P = 0.2;  // k_P² > k_C k_W: unstable at rest
  EXPECT_THROW(ReferenceFabric{p}, InputError);
  EXPECT_EQ(law.coefficient_names()[2], "eps_CL");
}
