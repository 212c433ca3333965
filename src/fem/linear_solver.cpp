// Eigen SimplicialLDLT / CHOLMOD / UMFPACK behind one interface (THEORY §4, §7).
#include "linear_solver.hpp"

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <chrono>

namespace tricot::fem::detail {

namespace {

// K's values numbered 1..nnz, so that a triangle extracted from it says where each entry comes from.
Eigen::SparseMatrix<double> numbered(const Eigen::SparseMatrix<double>& pattern) {
  Eigen::SparseMatrix<double> m = pattern;
  for (int k = 0; k < m.nonZeros(); ++k) m.valuePtr()[k] = k + 1;
  return m;
}

std::vector<int> sources(const Eigen::SparseMatrix<double>& tri) {
  std::vector<int> from(tri.nonZeros());
  for (int k = 0; k < tri.nonZeros(); ++k) from[k] = static_cast<int>(tri.valuePtr()[k]) - 1;
  return from;
}

// Y ← L⁻ᵀ D⁻¹ L⁻¹ Y for M columns of a row-major block (row stride m), L unit lower triangular
// (strict part in CSC).
template <int M>
void ldlt_substitute(Eigen::Index n, const int* Lp, const int* Li, const double* Lx, const Eigen::VectorXd& D,
                     double* Y, Eigen::Index m) {
  using Row = Eigen::Matrix<double, 1, M>;
  using RowMap = Eigen::Map<Row>;
  for (Eigen::Index j = 0; j < n; ++j) {  // L y = b
    const Row yj = RowMap(Y + j * m);
    for (int p = Lp[j]; p < Lp[j + 1]; ++p) RowMap(Y + static_cast<Eigen::Index>(Li[p]) * m) -= Lx[p] * yj;
  }
  for (Eigen::Index j = 0; j < n; ++j) RowMap(Y + j * m) /= D(j);
  auto row = [&](int p) { return RowMap(Y + static_cast<Eigen::Index>(Li[p]) * m); };
  for (Eigen::Index j = n - 1; j >= 0; --j) {  // Lᵀ z = D⁻¹ y: a dot product per row, in 4 chains
    Row a0 = RowMap(Y + j * m), a1 = Row::Zero(), a2 = Row::Zero(), a3 = Row::Zero();
    int p = Lp[j];
    for (const int end = Lp[j + 1]; p + 3 < end; p += 4) {
      a0 -= Lx[p] * row(p);
      a1 -= Lx[p + 1] * row(p + 1);
      a2 -= Lx[p + 2] * row(p + 2);
      a3 -= Lx[p + 3] * row(p + 3);
    }
    for (; p < Lp[j + 1]; ++p) a0 -= Lx[p] * row(p);
    RowMap(Y + j * m) = (a0 + a1) + (a2 + a3);
  }
}

}  // namespace

LinearSolver::LinearSolver(const Eigen::SparseMatrix<double>& pattern, LinearSolverKind kind)
    : kind_(kind), n_(pattern.rows()) {
  if (n_ == 0) return;
  const Eigen::SparseMatrix<double> marked = numbered(pattern);
  if (kind_ == LinearSolverKind::eigen_ldlt) {
    // AMD on the symmetric pattern, then the upper triangle of P K Pᵀ: SimplicialLDLT with the
    // natural ordering factorizes it in place, without the permuted copy it makes otherwise.
    Eigen::AMDOrdering<int> amd;
    amd(marked, Pinv_);
    P_ = Pinv_.inverse();
    tri_.resize(n_, n_);
    tri_.template selfadjointView<Eigen::Upper>() = marked.template selfadjointView<Eigen::Lower>().twistedBy(P_);
    tri_.makeCompressed();
    ldlt_ = std::make_unique<Ldlt>();
    ldlt_->analyzePattern(tri_);
  } else {
    // CHOLMOD reads one triangle; handing it only that one saves a transpose per factorization.
    tri_ = marked.triangularView<Eigen::Lower>();
    tri_.makeCompressed();
    cholmod_ = std::make_unique<Cholmod>();
    // Simplicial LDLᵀ: for 2-D meshes of a few thousand dofs it beats the supernodal LLᵀ with Debian's
    // reference BLAS (bench/fem_benchmark.cpp, docs/validation.md).
    cholmod_->setMode(Eigen::CholmodLDLt);
    cholmod_->cholmod().print = 0;  // the library never prints (STYLE.md §4): failures come back as info()
    cholmod_->analyzePattern(tri_);
  }
  from_ = sources(tri_);
}

bool LinearSolver::factorize(const Eigen::SparseMatrix<double>& K, bool symmetric) {
  if (n_ == 0) return true;
  const auto t0 = std::chrono::steady_clock::now();
  ++factorizations;
  bool ok = false;
  lu_active_ = false;
  if (symmetric) {
    const double* v = K.valuePtr();
    double* t = tri_.valuePtr();
    for (size_t k = 0; k < from_.size(); ++k) t[k] = v[from_[k]];
    if (ldlt_) {
      ldlt_->factorize(tri_);
      ok = ldlt_->info() == Eigen::Success;
    } else {
      cholmod_->factorize(tri_);
      ok = cholmod_->info() == Eigen::Success;
    }
  }
  if (!ok) {  // not symmetric, or singular for LDLᵀ without pivoting: LU
    if (!lu_) {
      lu_ = std::make_unique<Eigen::UmfPackLU<Eigen::SparseMatrix<double>>>();
      // No refinement inside UMFPACK's solve (its default is 2 sweeps, each a product with K): Newton
      // corrects its own steps, and the sensitivities match finite differences without it
      // (tests/fem/solver_test.cpp, Sensitivities.*).
      lu_->umfpackControl()(UMFPACK_IRSTEP) = 0;
      lu_->analyzePattern(K);
    }
    lu_->factorize(K);
    ok = lu_->info() == Eigen::Success;
    lu_active_ = ok;
  }
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return ok;
}

void LinearSolver::solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) const {
  if (n_ == 0) {
    x.resize(0, b.cols());
    return;
  }
  if (lu_active_) {
    x = lu_->solve(b);
  } else if (ldlt_) {
    // x = Pᵀ L⁻ᵀ D⁻¹ L⁻¹ P b on a row-major copy: the columns of b go through L together, so that L
    // (which does not fit in cache) is read twice per solve, not twice per column.
    const auto& L = ldlt_->matrixL().nestedExpression();  // strictly lower part, unit diagonal implied
    const int* Lp = L.outerIndexPtr();
    const int* Li = L.innerIndexPtr();
    const double* Lx = L.valuePtr();
    const Eigen::VectorXd& D = ldlt_->vectorD();
    const Eigen::Index m = b.cols();
    const int* perm = P_.indices().data();
    work_.resize(n_, m);
    double* Y = work_.data();
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index c = 0; c < m; ++c) Y[perm[i] * m + c] = b(i, c);
    for (Eigen::Index c0 = 0; c0 < m; c0 += 4) {  // blocks of ≤ 4 columns: a compile-time width keeps rows in registers
      switch (std::min<Eigen::Index>(4, m - c0)) {
        case 1: ldlt_substitute<1>(n_, Lp, Li, Lx, D, Y + c0, m); break;
        case 2: ldlt_substitute<2>(n_, Lp, Li, Lx, D, Y + c0, m); break;
        case 3: ldlt_substitute<3>(n_, Lp, Li, Lx, D, Y + c0, m); break;
        default: ldlt_substitute<4>(n_, Lp, Li, Lx, D, Y + c0, m); break;
      }
    }
    x.resize(n_, m);
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index c = 0; c < m; ++c) x(i, c) = Y[perm[i] * m + c];
  } else {
    x = cholmod_->solve(b);
  }
}

}  // namespace tricot::fem::detail
