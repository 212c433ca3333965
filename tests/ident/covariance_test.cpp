#include "tricot/ident/covariance.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "analytic.hpp"
#include "tricot/ident/identify.hpp"

namespace tricot::ident {
namespace {

// The SVD route and the normal equations agree to round-off for a well-conditioned A.
constexpr double kClosedForm = 1e-10;

// y = A p: a straight line through 40 points, p = (intercept, slope, curvature).
Eigen::MatrixXd design() {
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(40, 0, 3);
  Eigen::MatrixXd A(40, 3);
  A.col(0).setOnes();
  A.col(1) = t;
  A.col(2) = t.cwiseAbs2();
  return A;
}

TEST(Uncertainty, LinearModelWithKnownSigmaGivesSigmaSquaredTimesInverseNormalMatrix) {
  const Eigen::MatrixXd A = design();
  const Eigen::Vector3d truth(1.0, 0.5, -0.2);
  const double sigma = 0.03;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, sigma);
  Eigen::VectorXd y = A * truth;
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += noise(rng);
  const Eigen::MatrixXd AA = A;
  test::AnalyticProblem p(
      {Parameter{"a", 1.0}, Parameter{"b", 1.0}, Parameter{"c", -1.0}},
      [AA](const Eigen::VectorXd& J) { return (AA * J).eval(); }, [AA](const Eigen::VectorXd&) { return AA; }, y,
      sigma);
  IdentifyOptions o;
  o.delta = 1e-12;  // run to round-off, to compare with the closed form
  o.epsilon = 0;
  o.function_tolerance = 0;
  const IdentifyResult r = identify(p, o);
  ASSERT_TRUE(r.converged()) << r.message;
  // The least-squares solution and its covariance in closed form.
  const Eigen::MatrixXd N = (A.transpose() * A).inverse();
  const Eigen::Vector3d p_hat = N * A.transpose() * y;
  EXPECT_LT((r.parameters - p_hat).cwiseAbs().maxCoeff(), 1e-9);
  const Eigen::MatrixXd cov = sigma * sigma * N;
  EXPECT_TRUE(r.uncertainty.from_sigma);
  EXPECT_LT((r.uncertainty.covariance - cov).cwiseAbs().maxCoeff() / cov.cwiseAbs().maxCoeff(), kClosedForm);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(r.uncertainty.std_error(k), std::sqrt(cov(k, k)), kClosedForm * std::sqrt(cov(k, k)));
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(r.uncertainty.correlation(k, j), cov(k, j) / std::sqrt(cov(k, k) * cov(j, j)), 1e-10);
  }
}

TEST(Uncertainty, WithoutSigmaEstimatesItFromTheResiduals) {
  const Eigen::MatrixXd A = design();
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(40, -1, 1) * 0.01;
  const Eigen::Vector3d J(1.0, 0.5, -0.2);
  const Uncertainty u = uncertainty(A, r, J, J.cwiseAbs());
  const double s2 = r.squaredNorm() / (40 - 3);  // 2f/(N − n)
  EXPECT_DOUBLE_EQ(u.sigma2, s2);
  const Eigen::MatrixXd cov = s2 * (A.transpose() * A).inverse();
  EXPECT_LT((u.covariance - cov).cwiseAbs().maxCoeff() / cov.cwiseAbs().maxCoeff(), kClosedForm);
}

TEST(Uncertainty, NamesTheDirectionTheDataCannotSee) {
  // Columns 0 and 1 nearly equal: only their sum is well determined; the weak direction is their
  // difference in relative units (J = 1, so relative = absolute).
  Eigen::MatrixXd S(30, 3);
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(30, 0, 1);
  S.col(0) = t;
  S.col(1) = t + 1e-4 * t.cwiseAbs2();
  S.col(2) = Eigen::VectorXd::Ones(30);
  const Eigen::Vector3d J = Eigen::Vector3d::Ones();
  const Uncertainty u = uncertainty(S, Eigen::VectorXd::Zero(30), J, J);
  EXPECT_GT(u.condition_number, 1e4);
  EXPECT_NEAR(std::abs(u.least_identifiable(0)), std::sqrt(0.5), 1e-3);
  EXPECT_NEAR(u.least_identifiable(0), -u.least_identifiable(1), 1e-3);
  EXPECT_NEAR(u.correlation(0, 1), -1.0, 1e-3);

  S.col(1) = S.col(0);  // exactly collinear: rank-deficient
  const Uncertainty v = uncertainty(S, Eigen::VectorXd::Ones(30) * 1e-3, J, J);
  EXPECT_FALSE(v.full_rank);
  EXPECT_TRUE(std::isinf(v.condition_number));
  EXPECT_TRUE(std::isinf(v.std_error(0)));
  EXPECT_TRUE(std::isfinite(v.std_error(2)));
}

TEST(Uncertainty, ATallJacobianWithAVarianceOfEveryValueGivesTheSandwichInClosedForm) {
  // 40 000 values (a cruciform's DIC field: longer than Eigen's 16 384-double stack limit, where the
  // SVD of the tall matrix crashed) with a σ of their own: (SᵀS)⁻¹ SᵀVS (SᵀS)⁻¹ in relative units.
  const Eigen::Index N = 40000, n = 4;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0, 1);
  Eigen::MatrixXd S(N, n);
  Eigen::VectorXd var(N);
  for (Eigen::Index i = 0; i < N; ++i) {
    const double t = double(i) / N;
    S.row(i) << 1, t, std::sin(6 * t), u01(rng);
    var(i) = 0.5 + u01(rng);
  }
  const Eigen::Vector4d J(2.0, -0.5, 1.0, 0.25);
  const Uncertainty u = uncertainty(S, Eigen::VectorXd::Zero(N), J, J.cwiseAbs(), var);
  const Eigen::MatrixXd S_rel = S * J.cwiseAbs().asDiagonal();
  const Eigen::MatrixXd Ninv = (S_rel.transpose() * S_rel).inverse();
  const Eigen::MatrixXd cov_rel = Ninv * S_rel.transpose() * var.asDiagonal() * S_rel * Ninv;
  const Eigen::MatrixXd cov = J.cwiseAbs().asDiagonal() * cov_rel * J.cwiseAbs().asDiagonal();
  EXPECT_TRUE(u.from_sigma);
  EXPECT_LT((u.covariance - cov).cwiseAbs().maxCoeff() / cov.cwiseAbs().maxCoeff(), kClosedForm);
}

}  // namespace
}  // namespace tricot::ident
