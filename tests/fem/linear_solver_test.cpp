// fem/linear_solver.cpp: the sparse LDLᵀ backends, the LU fall-back and a singular tangent. White-box:
// the engine's private header.
#include "linear_solver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

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
  const Eigen::MatrixXd r = K * x - b;
  return r.cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
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

// A 5-point grid of m × m unknowns with a symmetric pattern and non-symmetric values (as the
// response-surface tangent): `skew` moves weight from the lower to the upper neighbours.
Eigen::SparseMatrix<double> grid(int m, double skew, double shift = 0) {
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const int k = j * m + i;
      t.emplace_back(k, k, 4.5 + shift + 0.01 * (k % 7));
      if (i + 1 < m) t.emplace_back(k, k + 1, -1 - skew), t.emplace_back(k + 1, k, -1 + skew);
      if (j + 1 < m) t.emplace_back(k, k + m, -1 + 0.5 * skew), t.emplace_back(k + m, k, -1 - 0.5 * skew);
    }
  Eigen::SparseMatrix<double> K(m * m, m * m);
  K.setFromTriplets(t.begin(), t.end());
  K.makeCompressed();
  return K;
}

TEST(LinearSolver, ASmallNonSymmetricTangentIsSolvedBySimplicialLuAsByUmfpack) {
  const Eigen::SparseMatrix<double> K = grid(9, 0.4);
  const Eigen::MatrixXd b = right_hand_sides(81);
  LinearSolver simplicial(K, LinearSolverKind::eigen_ldlt), umfpack(K, LinearSolverKind::cholmod_ldlt);
  ASSERT_TRUE(simplicial.factorize(K, false));
  ASSERT_TRUE(umfpack.factorize(K, false));
  EXPECT_EQ(simplicial.simplicial_lu_fallbacks, 0);
  EXPECT_NE(simplicial.description().find("simplicial LU"), std::string::npos);
  Eigen::MatrixXd x, x_umfpack;
  simplicial.solve(b, x);
  umfpack.solve(b, x_umfpack);
  EXPECT_LT(relative_residual(K, x, b), kSolve);
  EXPECT_LT((x - x_umfpack).cwiseAbs().maxCoeff() / x_umfpack.cwiseAbs().maxCoeff(), kSolve);
  // The next tangent (new values, same pattern) is factorized afresh: 5 columns, one block of 4 and one of 1.
  const Eigen::SparseMatrix<double> K2 = grid(9, -0.3, 1.0);
  ASSERT_TRUE(simplicial.factorize(K2, false));
  Eigen::MatrixXd b5(81, 5);
  for (int c = 0; c < 5; ++c) b5.col(c) = b.col(c % 2) * (c + 1) + Eigen::VectorXd::Constant(81, c);
  simplicial.solve(b5, x);
  EXPECT_LT(relative_residual(K2, x, b5), kSolve);
}

// From LinearSolver::kNestedDissectionFrom unknowns the block LU orders by nested dissection (METIS,
// whose random state is global): the answer is UMFPACK's, and two solvers built at once on two
// threads order alike, so they agree bit for bit.
TEST(LinearSolver, AMidSizeNonSymmetricTangentIsOrderedByNestedDissectionOnAnyThread) {
  const int m = 72;  // 5 184 unknowns
  ASSERT_TRUE(LinearSolver::nested_dissection(m * m));
  ASSERT_FALSE(LinearSolver::nested_dissection(LinearSolver::kNestedDissectionFrom - 1));
  ASSERT_FALSE(LinearSolver::nested_dissection(LinearSolver::kNestedDissectionBelow));
  const Eigen::SparseMatrix<double> K = grid(m, 0.4);
  const Eigen::MatrixXd b = right_hand_sides(m * m);
  Eigen::MatrixXd x[2];
  Eigen::Index entries[2];
  auto solve = [&](int k) {
    LinearSolver s(K, LinearSolverKind::eigen_ldlt);
    if (!s.factorize(K, false) || s.simplicial_lu_fallbacks != 0) return;
    s.solve(b, x[k]);
    entries[k] = s.lu_nonzeros();
    if (k == 0) {
      EXPECT_NE(s.description().find("nested-dissection"), std::string::npos);
    }
  };
  std::thread other(solve, 1);
  solve(0);
  other.join();
  ASSERT_EQ(x[0].rows(), m * m);
  ASSERT_EQ(x[1].rows(), m * m);
  EXPECT_EQ(entries[0], entries[1]);
  EXPECT_TRUE(x[0] == x[1]);
  LinearSolver umfpack(K, LinearSolverKind::cholmod_ldlt);
  ASSERT_TRUE(umfpack.factorize(K, false));
  Eigen::MatrixXd x_umfpack;
  umfpack.solve(b, x_umfpack);
  EXPECT_LT(relative_residual(K, x[0], b), kSolve);
  EXPECT_LT((x[0] - x_umfpack).cwiseAbs().maxCoeff() / x_umfpack.cwiseAbs().maxCoeff(), kSolve);
}

// A regular non-symmetric K whose elimination without pivoting meets a zero pivot: the simplicial LU
// gives up and UMFPACK answers.
void expect_umfpack_answers(const Eigen::SparseMatrix<double>& K) {
  LinearSolver s(K, LinearSolverKind::eigen_ldlt);
  ASSERT_TRUE(s.factorize(K, false));
  EXPECT_EQ(s.simplicial_lu_fallbacks, 1);
  const Eigen::MatrixXd b = right_hand_sides(static_cast<int>(K.rows()));
  Eigen::MatrixXd x;
  s.solve(b, x);
  EXPECT_LT(relative_residual(K, x, b), kSolve);
}

TEST(LinearSolver, ANonSymmetricTangentWithAZeroPivotFallsBackToUmfpack) {
  // [[0, 2], [1, 1]]: regular, but elimination without pivoting meets 0 first (AMD keeps the order of a 2 × 2).
  std::vector<Eigen::Triplet<double>> t{{0, 0, 0.0}, {0, 1, 2.0}, {1, 0, 1.0}, {1, 1, 1.0}};
  Eigen::SparseMatrix<double> K(2, 2);
  K.setFromTriplets(t.begin(), t.end());
  expect_umfpack_answers(K);
}

// The simplicial LU works on 2 × 2 node blocks (consecutive equations with the same pattern) and pads
// every other equation with a decoupled dummy: a chain of 12 two-dof nodes, each coupled to its
// neighbours within 2, the first node with one free dof only (a singleton, as on a symmetry edge),
// non-symmetric values. Same answer as UMFPACK, for 1 and 14 right-hand sides (the sensitivities').
TEST(LinearSolver, NodeBlocksWithASingletonGiveUmfpacksAnswer) {
  const int nodes = 12, n = 2 * nodes - 1;
  auto eq = [](int node, int dof) { return node == 0 ? (dof == 1 ? 0 : -1) : 2 * node - 1 + dof; };
  std::vector<Eigen::Triplet<double>> t;
  for (int a = 0; a < nodes; ++a)
    for (int b = std::max(0, a - 2); b <= std::min(nodes - 1, a + 2); ++b)
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          const int r = eq(a, i), c = eq(b, j);
          if (r < 0 || c < 0) continue;
          const double v = a == b ? (i == j ? 9.0 + 0.1 * r : 0.7 - 0.2 * i) : -0.5 - 0.03 * (r - c) + 0.1 * (i - j);
          t.emplace_back(r, c, v);
        }
  Eigen::SparseMatrix<double> K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  K.makeCompressed();
  LinearSolver blocks(K, LinearSolverKind::eigen_ldlt), umfpack(K, LinearSolverKind::cholmod_ldlt);
  ASSERT_TRUE(blocks.factorize(K, false));
  ASSERT_TRUE(umfpack.factorize(K, false));
  EXPECT_EQ(blocks.simplicial_lu_fallbacks, 0);
  EXPECT_GT(blocks.lu_nonzeros(), 0);  // the block LU, not UMFPACK, answered
  for (int m : {1, 14}) {
    Eigen::MatrixXd b(n, m);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < m; ++c) b(i, c) = std::sin(1.0 + i + 3.0 * c);
    Eigen::MatrixXd x, x_umfpack;
    blocks.solve(b, x);
    umfpack.solve(b, x_umfpack);
    EXPECT_LT(relative_residual(K, x, b), kSolve) << m;
    EXPECT_LT((x - x_umfpack).cwiseAbs().maxCoeff() / x_umfpack.cwiseAbs().maxCoeff(), kSolve) << m;
  }
}

// The tiny-pivot test looks at both pivots of a node block: K = [[S, I], [I, S]], S = [[1, 1], [1, 1]]
// (regular: eigenvalues of S ± I are 3, 1, 1, −1), whichever block comes first its second pivot is 0.
TEST(LinearSolver, ABlocksZeroSecondPivotFallsBackToUmfpack) {
  const double k[4][4] = {{1, 1, 1, 0}, {1, 1, 0, 1}, {1, 0, 1, 1}, {0, 1, 1, 1}};
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) t.emplace_back(i, j, k[i][j]);  // zeros kept: one pattern for all rows
  Eigen::SparseMatrix<double> K(4, 4);
  K.setFromTriplets(t.begin(), t.end());
  expect_umfpack_answers(K);
}

// UMFPACK's several right-hand sides go through its factors together (solve_lu_columns): the same
// answer as its own solve of each column. The matrix: a diagonally dominant grid operator with
// convection (non-symmetric), rows 10m and 10m + 1 swapped, so that rows 10m start with a zero on the
// diagonal and UMFPACK must pivot (P ≠ Q), at the condition of the dominant operator.
TEST(LinearSolver, UmfpackSolvesSeveralColumnsTogetherAsOneByOne) {
  const int g = 20, n = g * g;
  auto row = [](int k) { return k % 10 == 0 ? k + 1 : k % 10 == 1 ? k - 1 : k; };  // the swap
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      const int k = i * g + j;
      t.emplace_back(row(k), k, 6.0);
      // the (k + 1, k) coupling of a swapped pair is 0: it lands on the diagonal
      if (j + 1 < g) t.emplace_back(row(k), k + 1, -0.4), t.emplace_back(row(k + 1), k, k % 10 == 0 ? 0.0 : -1.6);
      if (i + 1 < g) t.emplace_back(row(k), k + g, -0.7), t.emplace_back(row(k + g), k, -1.3);
    }
  Eigen::SparseMatrix<double> K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  ASSERT_EQ(K.coeff(0, 0), 0.0);
  LinearSolver s(K, LinearSolverKind::cholmod_supernodal);  // non-symmetric: UMFPACK
  ASSERT_TRUE(s.factorize(K, false));
  Eigen::MatrixXd b(n, 5);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 5; ++c) b(i, c) = std::sin(0.37 * i + c) + c;
  Eigen::MatrixXd x, xc;
  s.solve(b, x);
  EXPECT_LT(relative_residual(K, x, b), 1e-12);
  for (int c = 0; c < 5; ++c) {
    s.solve(b.col(c), xc);
    EXPECT_LT((x.col(c) - xc).cwiseAbs().maxCoeff(), 1e-12 * xc.cwiseAbs().maxCoeff()) << "column " << c;
  }
}

}  // namespace
}  // namespace tricot::fem::detail
