// Sparse direct solution of the free-free tangent (THEORY §4, §7), private to fem: CHOLMOD's
// Cholesky (LDLᵀ) when the tangent is symmetric, UMFPACK LU when it is not or LDLᵀ breaks down. The symbolic analysis is done
// once per simulation (the pattern is fixed); each Newton iteration only factorizes numerically.
#pragma once

#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <Eigen/UmfPackSupport>
#include <memory>
#include <vector>

namespace tricot::fem::detail {

class LinearSolver {
 public:
  /// Symbolic analysis of the pattern for CHOLMOD (UMFPACK's is done the first time it is needed).
  explicit LinearSolver(const Eigen::SparseMatrix<double>& pattern);
  /// Numeric factorization of K: LDLᵀ when `symmetric` (K's lower triangle), else or on a zero pivot LU.
  /// False when both fail (singular tangent).
  bool factorize(const Eigen::SparseMatrix<double>& K, bool symmetric);
  /// Solves K x = b with the last factorization (b may have several columns).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;
  bool used_lu() const { return lu_active_; }

  double seconds = 0;    ///< wall time in numeric factorizations
  int factorizations = 0;

 private:
  using Cholesky = Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>;
  std::unique_ptr<Cholesky> cholesky_;
  Eigen::SparseMatrix<double> lower_;  ///< the lower triangle handed to CHOLMOD
  std::vector<int> lower_from_;        ///< lower_.valuePtr()[k] = K.valuePtr()[lower_from_[k]]
  std::unique_ptr<Eigen::UmfPackLU<Eigen::SparseMatrix<double>>> lu_;
  bool lu_active_ = false;
  Eigen::Index n_ = 0;
};

}  // namespace tricot::fem::detail
