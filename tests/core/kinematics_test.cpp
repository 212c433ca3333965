#include "tricot/core/kinematics.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "testing/fd_check.hpp"
#include "testing/record.hpp"
#include "testing/states.hpp"

using namespace tricot;
using tricot::test::JacobianMatches;
using tricot::test::record_scientific;
using tricot::test::rot;

namespace {

/// Central differences with h = 1e-6 are exact to ~1e-10 relative for these smooth maps; 1e-7 leaves room
/// for the λ = 3 stretch without hiding a wrong term (a wrong term is O(1)).
constexpr double kFdTol = 1e-7;
/// Identities that hold to round-off (a few ulps of O(1) numbers).
constexpr double kRoundOff = 1e-13;

Mat2 from(const Eigen::VectorXd& x) { return unflatten(Vec4(x)); }
Eigen::VectorXd vec(const Mat2& A) { return flatten(A); }

/// The states the issue asks for: identity, tiny, large rotation, large stretch, repeated eigenvalues,
/// and a general one.
std::vector<test::State> states() {
  Mat2 tiny, general;
  tiny << 1 + 1e-8, 3e-9, -2e-9, 1 - 0.5e-8;
  general << 1.3, 0.4, -0.2, 0.8;
  Mat2 stretched;
  stretched << 1.4, 0.3, 0.3, 0.9;
  return {{"identity", Mat2::Identity()},
          {"tiny strain 1e-8", tiny},
          {"large rotation 170 deg", rot(170) * stretched},
          {"large stretch 3", Vec2(3.0, 1.0 / 3.0).asDiagonal()},
          {"repeated eigenvalues U = 2I rotated 60 deg", rot(60) * (2 * Mat2::Identity())},
          {"general", general}};
}

}  // namespace

TEST(PolarDecomposition, ReconstructsFWithARotationAndASymmetricPositiveStretch) {
  for (const auto& s : states()) {
    const PolarDecomposition p = polar_decomposition(s.F);
    EXPECT_LT((p.R * p.U - s.F).norm(), kRoundOff) << s.name;
    EXPECT_LT((p.R.transpose() * p.R - Mat2::Identity()).norm(), kRoundOff) << s.name;
    EXPECT_NEAR(p.R.determinant(), 1.0, kRoundOff) << s.name;
    EXPECT_EQ(p.U(0, 1), p.U(1, 0)) << s.name;
    EXPECT_GT(p.U.trace(), 0) << s.name;
    EXPECT_GT(p.U.determinant(), 0) << s.name;
  }
}

TEST(PolarDecomposition, FindsTheAngleOfARigidRotation) {
  for (double deg : {0.0, 30.0, 90.0, 170.0, -135.0}) {
    const PolarDecomposition p = polar_decomposition(rot(deg) * Vec2(2.0, 0.5).asDiagonal());
    EXPECT_NEAR(p.theta, deg * std::numbers::pi / 180, kRoundOff) << deg;
    EXPECT_LT((p.U - Mat2(Vec2(2.0, 0.5).asDiagonal())).norm(), kRoundOff) << deg;
  }
}

TEST(PolarDecomposition, AngleRotationAndStretchDerivativesMatchFiniteDifferences) {
  double worst = 0;
  for (const auto& s : states()) {
    PolarJacobians J;
    polar_decomposition(s.F, &J);
    auto theta = [](const Eigen::VectorXd& x) {
      return Eigen::VectorXd::Constant(1, polar_decomposition(from(x)).theta);
    };
    auto R = [](const Eigen::VectorXd& x) { return vec(polar_decomposition(from(x)).R); };
    auto U = [](const Eigen::VectorXd& x) { return vec(polar_decomposition(from(x)).U); };
    EXPECT_TRUE(JacobianMatches(theta, vec(s.F), Eigen::MatrixXd(J.dtheta_dF.transpose()), kFdTol)) << s.name;
    EXPECT_TRUE(JacobianMatches(R, vec(s.F), J.dR_dF, kFdTol)) << s.name;
    EXPECT_TRUE(JacobianMatches(U, vec(s.F), J.dU_dF, kFdTol)) << s.name;
    worst = std::max({worst, tricot::test::jacobian_error(theta, vec(s.F), Eigen::MatrixXd(J.dtheta_dF.transpose())),
                      tricot::test::jacobian_error(R, vec(s.F), J.dR_dF),
                      tricot::test::jacobian_error(U, vec(s.F), J.dU_dF)});
  }
  record_scientific("max_polar_fd_rel_error", worst);
}

TEST(LogDividedDifference, IsTheSlopeOfTheLogAndItsLimitAtEqualArguments) {
  EXPECT_DOUBLE_EQ(log_divided_difference(2.0, 2.0), 0.5);
  EXPECT_DOUBLE_EQ(log_divided_difference(3.0, 1.0), std::log(3.0) / 2);
  EXPECT_DOUBLE_EQ(log_divided_difference(0.2, 5.0), (std::log(0.2) - std::log(5.0)) / (0.2 - 5.0));
  // (ln(1+δ))/δ = 1 − δ/2 + δ²/3: the naive quotient would lose ~7 digits here.
  const double delta = 1e-9;
  EXPECT_NEAR(log_divided_difference(1 + delta, 1.0), 1 - delta / 2 + delta * delta / 3, 1e-16);
  // Continuity across the series switch (|t|² = 1e-3 near a/b = 1.065).
  for (double r : {1.0649, 1.0651, 1.0650}) {
    EXPECT_NEAR(log_divided_difference(r, 1.0), std::log(r) / (r - 1), 1e-14) << r;
  }
}

TEST(LogSpd, IsTheLogOfTheEigenvaluesInTheEigenbasis) {
  for (double deg : {0.0, 25.0, 90.0, 133.0}) {
    const Mat2 N = rot(deg);
    const Mat2 U = N * Vec2(3.0, 0.4).asDiagonal() * N.transpose();
    const Mat2 expected = N * Vec2(std::log(3.0), std::log(0.4)).asDiagonal() * N.transpose();
    EXPECT_LT((log_spd(U) - expected).norm(), kRoundOff) << deg;
  }
  EXPECT_LT((log_spd(2 * Mat2::Identity()) - std::log(2.0) * Mat2::Identity()).norm(), kRoundOff);
}

TEST(LogSpd, DerivativeIsOneOverLambdaTimesIdentityAtRepeatedEigenvalues) {
  Mat4 J;
  log_spd(2.5 * Mat2::Identity(), &J);
  EXPECT_LT((J - Mat4::Identity() / 2.5).norm(), kRoundOff);
}

TEST(LogSpd, DerivativeMatchesFiniteDifferencesInEveryDirection) {
  Mat2 nearly_repeated;  // eigenvalues 2 ± 1e-7: inside the series branch
  nearly_repeated << 2.0 + 1e-7, 0, 0, 2.0 - 1e-7;
  std::vector<Mat2> Us = {nearly_repeated, 2 * Mat2::Identity()};
  for (const auto& s : states()) Us.push_back(polar_decomposition(s.F).U);
  auto logU = [](const Eigen::VectorXd& x) { return vec(log_spd(from(x))); };
  double worst = 0;
  for (const Mat2& U : Us) {
    Mat4 J;
    log_spd(U, &J);
    EXPECT_TRUE(JacobianMatches(logU, vec(U), J, kFdTol)) << U;
    worst = std::max(worst, tricot::test::jacobian_error(logU, vec(U), J));
  }
  record_scientific("max_log_fd_rel_error", worst);
}

TEST(LogSpd, ChainedThroughThePolarDecompositionMatchesFiniteDifferencesInF) {
  auto logU = [](const Eigen::VectorXd& x) { return vec(log_spd(polar_decomposition(from(x)).U)); };
  for (const auto& s : states()) {
    PolarJacobians JP;
    const PolarDecomposition p = polar_decomposition(s.F, &JP);
    Mat4 JL;
    log_spd(p.U, &JL);
    EXPECT_TRUE(JacobianMatches(logU, vec(s.F), JL * JP.dU_dF, kFdTol)) << s.name;
  }
}

TEST(GreenLagrange, IsHalfOfUSquaredMinusIdentityAndItsDerivativeMatchesFiniteDifferences) {
  auto E = [](const Eigen::VectorXd& x) { return vec(green_lagrange(from(x))); };
  for (const auto& s : states()) {
    Mat4 J;
    const Mat2 e = green_lagrange(s.F, &J);
    const Mat2 U = polar_decomposition(s.F).U;
    EXPECT_LT((e - 0.5 * (U * U - Mat2::Identity())).norm(), kRoundOff * (1 + U.squaredNorm())) << s.name;
    EXPECT_TRUE(JacobianMatches(E, vec(s.F), J, kFdTol)) << s.name;
  }
}

TEST(TensorProducts, LeftRightAndSandwichProductsAreTheDerivativesOfTheProducts) {
  Mat2 A, B, X;
  A << 1.0, 2.0, -0.5, 0.3;
  B << 0.7, -1.1, 0.4, 2.0;
  X << 0.2, -0.3, 1.5, 0.9;
  EXPECT_LT((unflatten(left_product(A) * flatten(X)) - A * X).norm(), kRoundOff);
  EXPECT_LT((unflatten(right_product(B) * flatten(X)) - X * B).norm(), kRoundOff);
  EXPECT_LT((unflatten(sandwich_product(A, B) * flatten(X)) - A * X * B).norm(), kRoundOff);
}
