// CHOLMOD / UMFPACK through Eigen's support modules (THEORY §4, §7).
#include "linear_solver.hpp"

#include <chrono>

namespace tricot::fem::detail {

LinearSolver::LinearSolver(const Eigen::SparseMatrix<double>& pattern) : n_(pattern.rows()) {
  if (n_ == 0) return;
  // CHOLMOD reads one triangle; handing it only that one saves a transpose per factorization.
  Eigen::SparseMatrix<double> marked = pattern;
  for (int k = 0; k < marked.nonZeros(); ++k) marked.valuePtr()[k] = k + 1;
  lower_ = marked.triangularView<Eigen::Lower>();
  lower_.makeCompressed();
  lower_from_.resize(lower_.nonZeros());
  for (int k = 0; k < lower_.nonZeros(); ++k) lower_from_[k] = static_cast<int>(lower_.valuePtr()[k]) - 1;
  cholesky_ = std::make_unique<Cholesky>();
  // Simplicial LDLᵀ: for 2-D meshes of a few thousand dofs it beats the supernodal LLᵀ with Debian's
  // reference BLAS, and needs no square roots (measured in bench/fem_benchmark.cpp, docs/validation/fem.md).
  cholesky_->setMode(Eigen::CholmodLDLt);
  cholesky_->cholmod().print = 0;  // the library never prints (STYLE.md §4): failures come back as info()
  cholesky_->analyzePattern(lower_);
}

bool LinearSolver::factorize(const Eigen::SparseMatrix<double>& K, bool symmetric) {
  if (n_ == 0) return true;
  const auto t0 = std::chrono::steady_clock::now();
  ++factorizations;
  bool ok = false;
  lu_active_ = false;
  if (symmetric) {
    const double* v = K.valuePtr();
    double* l = lower_.valuePtr();
    for (size_t k = 0; k < lower_from_.size(); ++k) l[k] = v[lower_from_[k]];
    cholesky_->factorize(lower_);
    ok = cholesky_->info() == Eigen::Success;
  }
  if (!ok) {  // not symmetric, or singular for LDLᵀ without pivoting: LU
    if (!lu_) {
      lu_ = std::make_unique<Eigen::UmfPackLU<Eigen::SparseMatrix<double>>>();
      lu_->analyzePattern(K);
    }
    lu_->factorize(K);
    ok = lu_->info() == Eigen::Success;
    lu_active_ = ok;
  }
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return ok;
}

Eigen::MatrixXd LinearSolver::solve(const Eigen::MatrixXd& b) const {
  if (n_ == 0) return Eigen::MatrixXd(0, b.cols());
  if (lu_active_) return lu_->solve(b);
  return cholesky_->solve(b);
}

}  // namespace tricot::fem::detail
