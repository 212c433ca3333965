// Eigen SimplicialLDLT / CHOLMOD / UMFPACK behind one interface (THEORY §4, §7).
#include "linear_solver.hpp"

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <chrono>
#include <cstdio>

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

// A CHOLMOD factorization of K's lower triangle in `mode`; supernodal ones on METIS nested
// dissection (2-D meshes: O(n^1.5) flops, less fill than AMD's; bench/linear_solver_benchmark.cpp).
std::unique_ptr<Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>> make_cholmod(
    Eigen::CholmodMode mode, bool metis) {
  auto c = std::make_unique<Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>>();
  c->setMode(mode);
  c->cholmod().print = 0;  // the library never prints (STYLE.md §4): failures come back as info()
  if (metis) {
    c->cholmod().nmethods = 1;
    c->cholmod().method[0].ordering = CHOLMOD_METIS;
    c->cholmod().postorder = 1;
  }
  return c;
}

}  // namespace

LinearSolver::LinearSolver(const Eigen::SparseMatrix<double>& pattern, LinearSolverKind kind)
    : kind_(kind), n_(pattern.rows()) {
  if (kind_ == LinearSolverKind::automatic)
    kind_ = n_ >= kSupernodalFrom ? LinearSolverKind::cholmod_supernodal : LinearSolverKind::eigen_ldlt;
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
    const bool supernodal = kind_ == LinearSolverKind::cholmod_supernodal;
    cholmod_ = make_cholmod(supernodal ? Eigen::CholmodSupernodalLLt : Eigen::CholmodLDLt, supernodal);
    cholmod_->analyzePattern(tri_);
  }
  from_ = sources(tri_);
}

bool LinearSolver::factorize(const Eigen::SparseMatrix<double>& K, bool symmetric) {
  if (n_ == 0) return true;
  const auto t0 = std::chrono::steady_clock::now();
  ++factorizations;
  active_ = Active::none;
  if (symmetric) {
    const double* v = K.valuePtr();
    double* t = tri_.valuePtr();
    for (size_t k = 0; k < from_.size(); ++k) t[k] = v[from_[k]];
    if (ldlt_) {
      ldlt_->factorize(tri_);
      if (ldlt_->info() == Eigen::Success) active_ = Active::eigen;
    } else {
      cholmod_->factorize(tri_);
      if (cholmod_->info() == Eigen::Success) active_ = Active::cholmod;
    }
    if (active_ == Active::none && kind_ == LinearSolverKind::cholmod_supernodal) {
      // Not positive definite (near an instability): LLᵀ stops at the first pivot ≤ 0, LDLᵀ without
      // pivoting goes on through negative pivots and solves the same system.
      ++ldlt_fallbacks;
      if (!cholmod_ldlt_) {
        cholmod_ldlt_ = make_cholmod(Eigen::CholmodLDLt, true);
        cholmod_ldlt_->analyzePattern(tri_);
      }
      cholmod_ldlt_->factorize(tri_);
      if (cholmod_ldlt_->info() == Eigen::Success) active_ = Active::cholmod_ldlt;
    }
    if (active_ == Active::none) ++lu_fallbacks;
  }
  if (active_ == Active::none) {  // not symmetric, or singular for LDLᵀ without pivoting: LU
    if (!lu_) {
      lu_ = std::make_unique<Eigen::UmfPackLU<Eigen::SparseMatrix<double>>>();
      // No refinement inside UMFPACK's solve (its default is 2 sweeps, each a product with K): Newton
      // corrects its own steps, and the sensitivities match finite differences without it
      // (tests/fem/solver_test.cpp, Sensitivities.*).
      lu_->umfpackControl()(UMFPACK_IRSTEP) = 0;
      // Large tangents: nested dissection (bench/linear_solver_benchmark.cpp, BM_Umfpack*).
      if (n_ >= kLuMetisFrom) lu_->umfpackControl()(UMFPACK_ORDERING) = UMFPACK_ORDERING_METIS;
      lu_->analyzePattern(K);
    }
    lu_->factorize(K);
    if (lu_->info() == Eigen::Success) active_ = Active::lu;
  }
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return active_ != Active::none;
}

std::string LinearSolver::description() const {
  const char* what = "";
  switch (kind_) {
    case LinearSolverKind::eigen_ldlt: what = "Eigen simplicial LDLT, AMD ordering"; break;
    case LinearSolverKind::cholmod_ldlt: what = "CHOLMOD simplicial LDLT, CHOLMOD's ordering"; break;
    case LinearSolverKind::cholmod_supernodal:
      what = "CHOLMOD supernodal LLT, METIS ordering (LDLT where not positive definite)";
      break;
    case LinearSolverKind::automatic: break;  // resolved in the constructor
  }
  char line[200];
  std::snprintf(line, sizeof line, "%s; UMFPACK LU, %s ordering, for non-symmetric tangents; %ld unknowns", what,
                n_ >= kLuMetisFrom ? "METIS" : "AMD", static_cast<long>(n_));
  return line;
}

void LinearSolver::solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) const {
  if (n_ == 0) {
    x.resize(0, b.cols());
    return;
  }
  if (active_ == Active::lu) {
    x = lu_->solve(b);
  } else if (active_ == Active::cholmod_ldlt) {
    x = cholmod_ldlt_->solve(b);
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
