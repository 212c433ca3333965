// fem/linear_solver.cpp: the sparse LDLᵀ backends, the LU fall-back and a singular tangent. White-box:
// the engine's private header.
#include "linear_solver.hpp"

#include <gtest/gtest.h>

namespace tricot::fem::detail {
namespace {

constexpr double kSolve = 1e-13;  // a 6 × 6 system of condition ~15: round-off of the residual

// A tridiagonal matrix: `diagonal` on the diagonal, `upper` above and `lower` below it.
Eigen::SparseMatrix<double> tridiagonal(int n, double diagonal, double upper, double lower) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, diagonal);
    if (i + 1 < n) t.emplace_back(i, i + 1, upper), t.emplace_back(i + 1, i, lower);
  }
  Eigen::SparseMatrix<double> K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  return K;
}

Eigen::MatrixXd right_hand_sides(int n) {
  Eigen::MatrixXd b(n, 2);
  for (int i = 0; i < n; ++i) b(i, 0) = 1 + i, b(i, 1) = (i % 2 ? -1.0 : 2.0);
  return b;
}

double relative_residual(const Eigen::SparseMatrix<double>& K, const Eigen::MatrixXd& x, const Eigen::MatrixXd& b) {
  return (Eigen::MatrixXd(K) * x - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

TEST(LinearSolver, BothLdltBackendsSolveASymmetricSystem) {
  const Eigen::SparseMatrix<double> K = tridiagonal(6, 4, -1, -1);
  const Eigen::MatrixXd b = right_hand_sides(6);
  for (LinearSolverKind kind : {LinearSolverKind::eigen_ldlt, LinearSolverKind::cholmod_ldlt}) {
    LinearSolver s(K, kind);
    ASSERT_TRUE(s.factorize(K, true));
    Eigen::MatrixXd x;
    s.solve(b, x);
    EXPECT_LT(relative_residual(K, x, b), kSolve) << int(kind);
    EXPECT_EQ(s.factorizations, 1);
  }
}

TEST(LinearSolver, ANonSymmetricTangentIsSolvedByLu) {
  const Eigen::SparseMatrix<double> K = tridiagonal(6, 4, -1.5, -0.5);
  const Eigen::MatrixXd b = right_hand_sides(6);
  LinearSolver s(K, LinearSolverKind::eigen_ldlt);
  ASSERT_TRUE(s.factorize(K, false));
  Eigen::MatrixXd x;
  s.solve(b, x);
  EXPECT_LT(relative_residual(K, x, b), kSolve);
}

TEST(LinearSolver, ASingularTangentIsReported) {
  const Eigen::SparseMatrix<double> K = tridiagonal(2, 1, 1, 1);  // [[1, 1], [1, 1]]: rank 1
  LinearSolver s(K, LinearSolverKind::eigen_ldlt);
  EXPECT_FALSE(s.factorize(K, true));  // LDLᵀ meets a zero pivot, LU a singular matrix
}

}  // namespace
}  // namespace tricot::fem::detail
