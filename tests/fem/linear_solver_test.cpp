// fem/linear_solver.cpp: the sparse LDLᵀ backends, the LU fall-back and a singular tangent. White-box:
// the engine's private header.
#include "linear_solver.hpp"

#include <gtest/gtest.h>

namespace tricot::fem::detail {
namespace {

constexpr double kSolve = 1e-13;  // systems of condition ≤ 50: round-off of the residual

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

TEST(LinearSolver, EverySymmetricBackendSolvesASymmetricSystem) {
  const Eigen::SparseMatrix<double> K = tridiagonal(6, 4, -1, -1);
  const Eigen::MatrixXd b = right_hand_sides(6);
  for (LinearSolverKind kind : {LinearSolverKind::eigen_ldlt, LinearSolverKind::cholmod_ldlt,
                                LinearSolverKind::cholmod_supernodal, LinearSolverKind::automatic}) {
    LinearSolver s(K, kind);
    ASSERT_TRUE(s.factorize(K, true));
    Eigen::MatrixXd x;
    s.solve(b, x);
    EXPECT_LT(relative_residual(K, x, b), kSolve) << int(kind);
    EXPECT_EQ(s.factorizations, 1);
  }
}

TEST(LinearSolver, AnIndefiniteTangentFallsBackFromSupernodalLltToLdltWithTheSameAnswer) {
  // Eigenvalues 1 + 4 cos(kπ/7), k = 1..6: three negative, none near 0; LDLᵀ meets no zero pivot.
  const Eigen::SparseMatrix<double> K = tridiagonal(6, 1, 2, 2);
  const Eigen::MatrixXd b = right_hand_sides(6);
  LinearSolver supernodal(K, LinearSolverKind::cholmod_supernodal), eigen(K, LinearSolverKind::eigen_ldlt);
  ASSERT_TRUE(supernodal.factorize(K, true));
  ASSERT_TRUE(eigen.factorize(K, true));
  EXPECT_EQ(supernodal.ldlt_fallbacks, 1);
  EXPECT_EQ(supernodal.lu_fallbacks, 0);
  Eigen::MatrixXd x, x_eigen;
  supernodal.solve(b, x);
  eigen.solve(b, x_eigen);
  EXPECT_LT(relative_residual(K, x, b), kSolve);
  EXPECT_LT((x - x_eigen).cwiseAbs().maxCoeff() / x_eigen.cwiseAbs().maxCoeff(), kSolve);
  // The next positive definite tangent goes back to LLᵀ.
  const Eigen::SparseMatrix<double> spd = tridiagonal(6, 4, -1, -1);
  ASSERT_TRUE(supernodal.factorize(spd, true));
  EXPECT_EQ(supernodal.ldlt_fallbacks, 1);
  supernodal.solve(b, x);
  EXPECT_LT(relative_residual(spd, x, b), kSolve);
}

TEST(LinearSolver, TheAutomaticChoiceGoesSupernodalFromTheMeasuredCrossover) {
  const auto n = static_cast<int>(LinearSolver::kSupernodalFrom);
  EXPECT_EQ(LinearSolver(tridiagonal(n - 1, 4, -1, -1), LinearSolverKind::automatic).kind(),
            LinearSolverKind::eigen_ldlt);
  const Eigen::SparseMatrix<double> K = tridiagonal(n, 4, -1, -1);
  LinearSolver s(K, LinearSolverKind::automatic);
  EXPECT_EQ(s.kind(), LinearSolverKind::cholmod_supernodal);
  EXPECT_NE(s.description().find("supernodal"), std::string::npos);
  ASSERT_TRUE(s.factorize(K, true));
  const Eigen::MatrixXd b = Eigen::MatrixXd::Ones(n, 1);
  Eigen::MatrixXd x;
  s.solve(b, x);
  EXPECT_LT((K * x - b).cwiseAbs().maxCoeff(), kSolve);
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
