// Eigen SimplicialLDLT / CHOLMOD / UMFPACK behind one interface (THEORY §4, §7).
#include "linear_solver.hpp"

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <chrono>
#include <cmath>
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

// Y ← U⁻¹ D⁻¹ L⁻¹ Y for M columns of a row-major block (row stride m), L and Uᵀ unit lower triangular
// with the same pattern (strict parts in CSC, values Lx and Ux); LDLᵀ: Ux = Lx.
template <int M>
void ldu_substitute(Eigen::Index n, const int* Lp, const int* Li, const double* Lx, const double* Ux,
                    const Eigen::VectorXd& D, double* Y, Eigen::Index m) {
  using Row = Eigen::Matrix<double, 1, M>;
  using RowMap = Eigen::Map<Row>;
  for (Eigen::Index j = 0; j < n; ++j) {  // L y = b
    const Row yj = RowMap(Y + j * m);
    for (int p = Lp[j]; p < Lp[j + 1]; ++p) RowMap(Y + static_cast<Eigen::Index>(Li[p]) * m) -= Lx[p] * yj;
  }
  for (Eigen::Index j = 0; j < n; ++j) RowMap(Y + j * m) /= D(j);
  auto row = [&](int p) { return RowMap(Y + static_cast<Eigen::Index>(Li[p]) * m); };
  for (Eigen::Index j = n - 1; j >= 0; --j) {  // U z = D⁻¹ y: a dot product per row, in 4 chains
    Row a0 = RowMap(Y + j * m), a1 = Row::Zero(), a2 = Row::Zero(), a3 = Row::Zero();
    int p = Lp[j];
    for (const int end = Lp[j + 1]; p + 3 < end; p += 4) {
      a0 -= Ux[p] * row(p);
      a1 -= Ux[p + 1] * row(p + 1);
      a2 -= Ux[p + 2] * row(p + 2);
      a3 -= Ux[p + 3] * row(p + 3);
    }
    for (; p < Lp[j + 1]; ++p) a0 -= Ux[p] * row(p);
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
  if (!symmetric && kind_ == LinearSolverKind::eigen_ldlt) {
    if (factorize_simplicial_lu(K)) active_ = Active::simplicial_lu;
    else ++simplicial_lu_fallbacks;
  }
  if (active_ == Active::none) {  // not symmetric, or singular for LDLᵀ without pivoting: LU
    if (!lu_) {
      lu_ = std::make_unique<Eigen::UmfPackLU<Eigen::SparseMatrix<double>>>();
      // No refinement inside UMFPACK's solve (its default is 2 sweeps, each a product with K): Newton
      // corrects its own steps, and the sensitivities match finite differences without it
      // (tests/fem/solver_test.cpp, Sensitivities.*).
      lu_->umfpackControl()(UMFPACK_IRSTEP) = 0;
      // No row scaling: P K Q = L U exactly, so that solve_lu_columns needs only the factors and the
      // permutations (the tangent's rows are all forces in N, of one scale).
      lu_->umfpackControl()(UMFPACK_SCALE) = UMFPACK_SCALE_NONE;
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

// Up-looking LDU without pivoting (the LDL algorithm of Davis, ACM TOMS 31(4), 2005, with a second
// triangular solve for the row): row k of B gives, through the elimination tree's reach of column k,
//   y = L⁻¹ B(0:k, k),  w = U⁻ᵀ B(k, 0:k)ᵀ,  U(i, k) = y_i / D_i,  L(k, i) = w_i / D_i,
//   D_k = B_kk − Σ_i w_i y_i / D_i.
// A pivot |D_k| ≤ kTinyPivot · max |B(:, k)|, |B(k, :)| fails the factorization (UMFPACK then pivots).
bool LinearSolver::factorize_simplicial_lu(const Eigen::SparseMatrix<double>& K) {
  constexpr double kTinyPivot = 1e-10;  // growth beyond 1e10 would cost the sensitivities their digits
  const int n = static_cast<int>(n_);
  if (!simplicial_lu_) {
    auto f = std::make_unique<SimplicialLu>();
    // B = P K Pᵀ, B(perm[i], perm[j]) = K(i, j); entries numbered by their place in K's values.
    const Eigen::SparseMatrix<double> marked = numbered(K);
    const int* perm = P_.indices().data();
    std::vector<Eigen::Triplet<double>> up, low;
    for (int j = 0; j < marked.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(marked, j); it; ++it) {
        const int r = perm[it.row()], c = perm[it.col()];
        if (r <= c) up.emplace_back(r, c, it.value());
        if (r >= c) low.emplace_back(c, r, it.value());  // Bᵀ's upper triangle: row r of B as column r
      }
    f->upper.resize(n, n);
    f->upper.setFromTriplets(up.begin(), up.end());
    f->upper.makeCompressed();
    Eigen::SparseMatrix<double> lower(n, n);
    lower.setFromTriplets(low.begin(), low.end());
    lower.makeCompressed();
    if (lower.nonZeros() != f->upper.nonZeros()) return false;  // not a symmetric pattern
    const int* Ap = f->upper.outerIndexPtr();
    const int* Ai = f->upper.innerIndexPtr();
    for (int k = 0; k < f->upper.nonZeros(); ++k)
      if (lower.innerIndexPtr()[k] != Ai[k]) return false;
    f->upper_from = sources(f->upper);
    f->lower_from = sources(lower);
    // Symbolic: elimination tree and column counts of L.
    f->parent.assign(n, -1), f->flag.assign(n, -1), f->Lnz.assign(n, 0);
    for (int k = 0; k < n; ++k) {
      f->flag[k] = k;
      for (int p = Ap[k]; p < Ap[k + 1]; ++p)
        for (int i = Ai[p]; i < k && f->flag[i] != k; i = f->parent[i]) {
          if (f->parent[i] == -1) f->parent[i] = k;
          ++f->Lnz[i];
          f->flag[i] = k;
        }
    }
    f->Lp.assign(n + 1, 0);
    for (int k = 0; k < n; ++k) f->Lp[k + 1] = f->Lp[k] + f->Lnz[k];
    f->Li.resize(f->Lp[n]), f->Lx.resize(f->Lp[n]), f->Ux.resize(f->Lp[n]);
    f->Bu.resize(f->upper.nonZeros()), f->Bl.resize(f->upper.nonZeros());
    f->y.assign(n, 0.0), f->w.assign(n, 0.0), f->pattern.resize(n);
    f->D.resize(n);
    simplicial_lu_ = std::move(f);
  }
  SimplicialLu& f = *simplicial_lu_;
  const double* v = K.valuePtr();
  for (size_t k = 0; k < f.Bu.size(); ++k) f.Bu[k] = v[f.upper_from[k]], f.Bl[k] = v[f.lower_from[k]];
  const int* Ap = f.upper.outerIndexPtr();
  const int* Ai = f.upper.innerIndexPtr();
  double* __restrict y = f.y.data();
  double* __restrict w = f.w.data();
  int* __restrict Li = f.Li.data();
  double* __restrict Lx = f.Lx.data();
  double* __restrict Ux = f.Ux.data();
  const int* Lp = f.Lp.data();
  double* D = f.D.data();
  std::fill(f.flag.begin(), f.flag.end(), -1);
  for (int k = 0; k < n; ++k) {
    int top = n;
    f.flag[k] = k;
    f.Lnz[k] = 0;
    double scale = 0;
    for (int p = Ap[k]; p < Ap[k + 1]; ++p) {
      int i = Ai[p];
      y[i] += f.Bu[p];
      if (i < k) w[i] += f.Bl[p];
      scale = std::max({scale, std::abs(f.Bu[p]), std::abs(f.Bl[p])});
      int len = 0;
      for (; f.flag[i] != k; i = f.parent[i]) f.pattern[len++] = i, f.flag[i] = k;
      while (len > 0) f.pattern[--top] = f.pattern[--len];
    }
    double Dk = y[k];
    y[k] = 0;
    for (; top < n; ++top) {
      const int i = f.pattern[top];
      const double yi = y[i], wi = w[i];
      y[i] = w[i] = 0;
      const int p2 = Lp[i] + f.Lnz[i];
      for (int p = Lp[i]; p < p2; ++p) {
        const int r = Li[p];
        y[r] -= Lx[p] * yi;
        w[r] -= Ux[p] * wi;
      }
      const double Di = D[i];
      Dk -= wi * yi / Di;
      Li[p2] = k;
      Lx[p2] = wi / Di;
      Ux[p2] = yi / Di;
      ++f.Lnz[i];
    }
    if (!(std::abs(Dk) > kTinyPivot * scale) || !std::isfinite(Dk)) {
      std::fill(f.y.begin(), f.y.end(), 0.0), std::fill(f.w.begin(), f.w.end(), 0.0);  // a later one starts clean
      return false;
    }
    D[k] = Dk;
  }
  return true;
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
  std::snprintf(line, sizeof line, "%s; %sUMFPACK LU, %s ordering, for non-symmetric tangents; %ld unknowns", what,
                kind_ == LinearSolverKind::eigen_ldlt ? "simplicial LU without pivoting on the same ordering, else " : "",
                n_ >= kLuMetisFrom ? "METIS" : "AMD", static_cast<long>(n_));
  return line;
}

void LinearSolver::solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) const {
  if (n_ == 0) {
    x.resize(0, b.cols());
    return;
  }
  if (active_ == Active::lu) {
    if (b.cols() > 1) solve_lu_columns(b, x);
    else x = lu_->solve(b);
  } else if (active_ == Active::cholmod_ldlt) {
    x = cholmod_ldlt_->solve(b);
  } else if (active_ == Active::eigen || active_ == Active::simplicial_lu) {
    // x = Pᵀ U⁻¹ D⁻¹ L⁻¹ P b on a row-major copy: the columns of b go through L together, so that L
    // (which does not fit in cache) is read twice per solve, not twice per column.
    const int *Lp, *Li;
    const double *Lx, *Ux;
    const Eigen::VectorXd* D;
    Eigen::VectorXd D_ldlt;
    if (active_ == Active::eigen) {
      D_ldlt = ldlt_->vectorD();
      const auto& L = ldlt_->matrixL().nestedExpression();  // strictly lower part, unit diagonal implied
      Lp = L.outerIndexPtr(), Li = L.innerIndexPtr(), Lx = Ux = L.valuePtr();
      D = &D_ldlt;
    } else {
      const SimplicialLu& f = *simplicial_lu_;
      Lp = f.Lp.data(), Li = f.Li.data(), Lx = f.Lx.data(), Ux = f.Ux.data(), D = &f.D;
    }
    const Eigen::Index m = b.cols();
    const int* perm = P_.indices().data();
    work_.resize(n_, m);
    double* Y = work_.data();
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index c = 0; c < m; ++c) Y[perm[i] * m + c] = b(i, c);
    for (Eigen::Index c0 = 0; c0 < m; c0 += 4) {  // blocks of ≤ 4 columns: a compile-time width keeps rows in registers
      switch (std::min<Eigen::Index>(4, m - c0)) {
        case 1: ldu_substitute<1>(n_, Lp, Li, Lx, Ux, *D, Y + c0, m); break;
        case 2: ldu_substitute<2>(n_, Lp, Li, Lx, Ux, *D, Y + c0, m); break;
        case 3: ldu_substitute<3>(n_, Lp, Li, Lx, Ux, *D, Y + c0, m); break;
        default: ldu_substitute<4>(n_, Lp, Li, Lx, Ux, *D, Y + c0, m); break;
      }
    }
    x.resize(n_, m);
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index c = 0; c < m; ++c) x(i, c) = Y[perm[i] * m + c];
  } else {
    x = cholmod_->solve(b);
  }
}

void LinearSolver::solve_lu_columns(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) const {
  // L: UMFPACK returns it by rows (Lp, Lj), which Eigen keeps in a column-major object's arrays; U by
  // columns (Up, Ui). P[k]: the row of K that is pivot row k; Q[k]: the column of K that is pivot
  // column k. K x = b: L U y = (b[P[k]])_k, x[Q[k]] = y[k].
  const auto& L = lu_->matrixL();  // extracts the factors once per factorization (Eigen caches them)
  const auto& U = lu_->matrixU();
  const auto& P = lu_->permutationP();
  const auto& Q = lu_->permutationQ();
  const int *Lp = L.outerIndexPtr(), *Lj = L.innerIndexPtr(), *Up = U.outerIndexPtr(), *Ui = U.innerIndexPtr();
  const double *Lx = L.valuePtr(), *Ux = U.valuePtr();
  const Eigen::Index n = n_, m = b.cols();
  work_.resize(n, m);
  for (Eigen::Index k = 0; k < n; ++k) work_.row(k) = b.row(P(k));
  for (Eigen::Index i = 0; i < n; ++i) {  // L y = P b, L unit lower triangular by rows
    auto yi = work_.row(i);
    for (int p = Lp[i]; p < Lp[i + 1]; ++p)
      if (Lj[p] < i) yi.noalias() -= Lx[p] * work_.row(Lj[p]);
  }
  for (Eigen::Index j = n - 1; j >= 0; --j) {  // U z = y by columns: the diagonal, then the rows above
    double d = 0;
    for (int p = Up[j]; p < Up[j + 1]; ++p)
      if (Ui[p] == j) d = Ux[p];
    auto yj = work_.row(j);
    yj /= d;
    for (int p = Up[j]; p < Up[j + 1]; ++p)
      if (Ui[p] < j) work_.row(Ui[p]).noalias() -= Ux[p] * yj;
  }
  x.resize(n, m);
  for (Eigen::Index k = 0; k < n; ++k) x.row(Q(k)) = work_.row(k);
}

}  // namespace tricot::fem::detail
