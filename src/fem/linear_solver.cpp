// Eigen SimplicialLDLT / CHOLMOD / UMFPACK behind one interface (docs/theory.md §4, §7).
#include "linear_solver.hpp"

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <type_traits>
#include <utility>

// The vector helpers below (V8) return vectors by value: inlined and internal to this
// file, so the ABI change GCC warns about without -march=native (-Wpsabi) does not matter.
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wpsabi"
#elif defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

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

// A fill-reducing ordering of the symmetric block pattern C: perm[block] = its place. CHOLMOD's nested
// dissection (METIS bisections, CAMD on the parts), or Eigen's AMD. METIS keeps its random state in
// globals, so the calls take turns: the ordering is then the same on any number of threads.
std::vector<int> order_blocks(Eigen::SparseMatrix<double>& C, bool nested) {
  const int nb = static_cast<int>(C.rows());
  std::vector<int> perm(nb);
  if (nested) {
    static std::mutex metis;
    const std::lock_guard<std::mutex> lock(metis);
    C.makeCompressed();
    cholmod_sparse A = Eigen::viewAsCholmod(C);
    A.stype = 1;  // C is symmetric: its upper triangle says it all
    std::vector<int> order(nb), cparent(nb), cmember(nb);
    cholmod_common common;
    cholmod_start(&common);
    const bool ok =
        cholmod_nested_dissection(&A, nullptr, 0, order.data(), cparent.data(), cmember.data(), &common) > 0;
    cholmod_finish(&common);
    if (ok) {
      for (int k = 0; k < nb; ++k) perm[order[k]] = k;
      return perm;
    }
  }
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> Pinv;
  Eigen::AMDOrdering<int> amd;
  amd(C, Pinv);
  const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P = Pinv.inverse();
  std::copy(P.indices().data(), P.indices().data() + nb, perm.begin());
  return perm;
}

// The offset in v (8 doubles spare at its end) of its first 64-byte aligned element: a block's L and
// Uᵀ (or y and w) then share one cache line.
size_t aligned64(const std::vector<double>& v) {
  const auto a = reinterpret_cast<std::uintptr_t>(v.data());
  return ((64 - a % 64) % 64) / sizeof(double);
}

// Eight doubles: an entry's L and Uᵀ blocks, or a row's y and w (one AVX-512 register where -march
// has it, else two or four).
typedef double V8 __attribute__((vector_size(64)));
typedef std::int64_t I8 __attribute__((vector_size(64)));
inline V8 load8(const double* p) {
  V8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store8(double* p, const V8& v) { std::memcpy(p, &v, sizeof v); }
/// (m00 m10 m00 m10 | u00 u10 u00 u10) and (m01 m11 m01 m11 | u01 u11 u01 u11) of (L | Uᵀ) blocks.
#if defined(__clang__)
inline V8 columns0(const V8& m) { return __builtin_shufflevector(m, m, 0, 1, 0, 1, 4, 5, 4, 5); }
inline V8 columns1(const V8& m) { return __builtin_shufflevector(m, m, 2, 3, 2, 3, 6, 7, 6, 7); }
#else
inline V8 columns0(const V8& m) { return __builtin_shuffle(m, I8{0, 1, 0, 1, 4, 5, 4, 5}); }
inline V8 columns1(const V8& m) { return __builtin_shuffle(m, I8{2, 3, 2, 3, 6, 7, 6, 7}); }
#endif

// Y ← U⁻¹ D⁻¹ L⁻¹ Y for M columns of a row-major block (row stride m) on 2 × 2 blocks: block row I is
// rows 2I, 2I + 1. L(R, I) and U(I, R)ᵀ in block column I's entries p (row block Li[p]) at Lx + 8 p and
// Ux + 8 p, each column-major (m00 m10 m01 m11); Dinv: D's inverses, column-major.
template <int M>
void block_ldu_substitute(int nb, const int* Lp, const int* Li, const double* Lx, const double* Ux, const double* Dinv,
                          double* Y, Eigen::Index m) {
  using Row = Eigen::Matrix<double, 1, M>;
  using RowMap = Eigen::Map<Row>;
  auto row = [&](Eigen::Index r) { return RowMap(Y + r * m); };
  for (int j = 0; j < nb; ++j) {  // L y = b
    const Row y0 = row(2 * j), y1 = row(2 * j + 1);
    for (int p = Lp[j]; p < Lp[j + 1]; ++p) {
      const double* l = Lx + 8 * static_cast<size_t>(p);
      const Eigen::Index r = 2 * static_cast<Eigen::Index>(Li[p]);
      row(r) -= l[0] * y0 + l[2] * y1;
      row(r + 1) -= l[1] * y0 + l[3] * y1;
    }
  }
  for (int j = 0; j < nb; ++j) {
    const double* d = Dinv + 4 * j;
    const Row y0 = row(2 * j), y1 = row(2 * j + 1);
    row(2 * j) = d[0] * y0 + d[2] * y1;
    row(2 * j + 1) = d[1] * y0 + d[3] * y1;
  }
  for (int j = nb - 1; j >= 0; --j) {  // U z = D⁻¹ y: block row j, U(j, r) = (stored U(j, r)ᵀ)ᵀ
    Row a0 = row(2 * j), a1 = row(2 * j + 1), b0 = Row::Zero(), b1 = Row::Zero();
    for (int p = Lp[j]; p < Lp[j + 1]; ++p) {
      const double* u = Ux + 8 * static_cast<size_t>(p);
      const Eigen::Index r = 2 * static_cast<Eigen::Index>(Li[p]);
      const Row z0 = row(r), z1 = row(r + 1);
      a0 -= u[0] * z0;
      b0 -= u[1] * z1;
      a1 -= u[2] * z0;
      b1 -= u[3] * z1;
    }
    row(2 * j) = a0 + b0;
    row(2 * j + 1) = a1 + b1;
  }
}

// Calls f(std::integral_constant<int, w>{}) for 1 ≤ w ≤ kMaxWidth: kernels over a row of w right-hand
// sides with w known at compile time (the sensitivities' 14 columns in one pass, rows in registers).
constexpr int kMaxWidth = 16;
template <class F, int... W>
void with_width_impl(int w, F&& f, std::integer_sequence<int, W...>) {
  (void)((w == W + 1 ? (f(std::integral_constant<int, W + 1>{}), true) : false) || ...);
}
template <class F>
void with_width(int w, F&& f) {
  with_width_impl(w, f, std::make_integer_sequence<int, kMaxWidth>{});
}

// R −= K X for M columns of row-major blocks (row stride m): each entry of K updates a row of R.
template <int M>
void subtract_product(const Eigen::SparseMatrix<double>& K, const double* X, double* R, Eigen::Index m) {
  using Row = Eigen::Matrix<double, 1, M>;
  const int* Kp = K.outerIndexPtr();
  const int* Ki = K.innerIndexPtr();
  const double* Kx = K.valuePtr();
  for (Eigen::Index j = 0; j < K.outerSize(); ++j) {
    const Row xj = Eigen::Map<const Row>(X + j * m);
    for (int p = Kp[j]; p < Kp[j + 1]; ++p) Eigen::Map<Row>(R + static_cast<Eigen::Index>(Ki[p]) * m) -= Kx[p] * xj;
  }
}

// A CHOLMOD factorization of K's lower triangle in `mode`; supernodal ones on METIS nested
// dissection (2-D meshes: O(n^1.5) flops, less fill than AMD's; bench/linear_solver_benchmark.cpp).
std::unique_ptr<Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>> make_cholmod(
    Eigen::CholmodMode mode, bool metis) {
  auto c = std::make_unique<Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>>();
  c->setMode(mode);
  c->cholmod().print = 0;  // the library never prints (the library never prints): failures come back as info()
  if (metis) {
    c->cholmod().nmethods = 1;
    c->cholmod().method[0].ordering = CHOLMOD_METIS;
    c->cholmod().postorder = 1;
  }
  return c;
}

}  // namespace

void residual(const Eigen::SparseMatrix<double>& K, const Eigen::MatrixXd& b, const Eigen::MatrixXd& x,
              Eigen::MatrixXd& r) {
  if (x.cols() == 1 || !K.isCompressed()) {
    r.noalias() = b - K * x;
    return;
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor xr = x;
  RowMajor rr = b;
  const Eigen::Index m = x.cols();
  for (Eigen::Index c0 = 0; c0 < m;) {  // blocks of up to 16 columns, each width at compile time
    const int w = static_cast<int>(std::min<Eigen::Index>(kMaxWidth, m - c0));
    with_width(w, [&](auto width) { subtract_product<decltype(width)::value>(K, xr.data() + c0, rr.data() + c0, m); });
    c0 += w;
  }
  r = rr;
}

LinearSolver::LinearSolver(const Eigen::SparseMatrix<double>& pattern, LinearSolverKind kind)
    : kind_(kind), n_(pattern.rows()) {
  // Non-symmetric tangents: the block LU with eigen_ldlt, and under `automatic` up to kBlockLuBelow
  // unknowns whatever takes the symmetric ones; an explicit CHOLMOD kind keeps UMFPACK.
  block_lu_ = kind_ == LinearSolverKind::eigen_ldlt || (kind_ == LinearSolverKind::automatic && n_ < kBlockLuBelow);
  if (kind_ == LinearSolverKind::automatic)
    kind_ = n_ >= kSupernodalFrom ? LinearSolverKind::cholmod_supernodal : LinearSolverKind::eigen_ldlt;
}

void LinearSolver::analyze_symmetric(const Eigen::SparseMatrix<double>& pattern) {
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
  if (symmetric && !ldlt_ && !cholmod_) analyze_symmetric(K);  // not timed: symbolic (K has the pattern)
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
  if (!symmetric && block_lu_) {
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
// triangular solve for the row) on 2 × 2 blocks: block row K of B gives, through the elimination tree's
// reach of block column K,
//   Y = L⁻¹ B(0:K, K),  W = U⁻ᵀ B(K, 0:K)ᵀ,  U(I, K) = D_I⁻¹ Y_I,  L(K, I) = W_Iᵀ D_I⁻¹,
//   D_K = B_KK − Σ_I L(K, I) Y_I.
// D_K's scalar LDU (d1 = D_K(0, 0), d2 = D_K(1, 1) − D_K(1, 0) D_K(0, 1) / d1) has the scalar LU's pivots
// of the block's two unknowns; a pivot |d| ≤ kTinyPivot · max |B(:, k)|, |B(k, :)| (over blocks ≤ K)
// fails the factorization (UMFPACK then pivots).
bool LinearSolver::factorize_simplicial_lu(const Eigen::SparseMatrix<double>& K) {
  constexpr double kTinyPivot = 1e-10;  // growth beyond 1e10 would cost the sensitivities their digits
  if (!K.isCompressed()) {              // the maps below index K's arrays directly (the assembler's K is compressed)
    Eigen::SparseMatrix<double> compressed = K;
    compressed.makeCompressed();
    return factorize_simplicial_lu(compressed);
  }
  const int n = static_cast<int>(n_);
  const int nnz = static_cast<int>(K.nonZeros());
  const int* Kp = K.outerIndexPtr();
  const int* Ki = K.innerIndexPtr();
  if (!simplicial_lu_) {
    auto f = std::make_unique<SimplicialLu>();
    // Blocks: equation e and e + 1 together when their columns (the pattern is symmetric) have the
    // same rows, each other equation alone with a dummy.
    auto same = [&](int e) {
      return Kp[e + 1] - Kp[e] == Kp[e + 2] - Kp[e + 1] && std::equal(Ki + Kp[e], Ki + Kp[e + 1], Ki + Kp[e + 1]);
    };
    std::vector<int> block(n), slot(n);
    int nb = 0;
    for (int e = 0; e < n; ++nb)
      if (e + 1 < n && same(e)) block[e] = block[e + 1] = nb, slot[e] = 0, slot[e + 1] = 1, e += 2;
      else block[e] = nb, slot[e] = 0, e += 1;
    std::vector<int> dofs(2 * nb, -1);  // block → its equations (−1: dummy)
    for (int e = 0; e < n; ++e) dofs[2 * block[e] + slot[e]] = e;
    // The block pattern, ordered; B's block (perm[I], perm[J]) = K's block (I, J).
    std::vector<Eigen::Triplet<double>> t;
    for (int j = 0; j < n; ++j)
      for (int p = Kp[j]; p < Kp[j + 1]; ++p) t.emplace_back(block[Ki[p]], block[j], 1.0);
    Eigen::SparseMatrix<double> C(nb, nb);
    C.setFromTriplets(t.begin(), t.end());
    const std::vector<int> perm = order_blocks(C, uses_nested_dissection());  // block → its place
    f->pos.resize(n);
    for (int e = 0; e < n; ++e) f->pos[e] = 2 * perm[block[e]] + slot[e];
    std::vector<int> at(2 * nb, -1);  // padded row → equation (−1: dummy)
    for (int e = 0; e < n; ++e) at[f->pos[e]] = e;
    // The upper block triangle of B: block entries (I ≤ J) by columns, sorted.
    std::vector<std::vector<int>> rows(nb);
    for (int j = 0; j < C.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(C, j); it; ++it) {
        const int I = perm[it.row()], J = perm[j];
        if (I <= J) rows[J].push_back(I);
      }
    f->Ap.assign(nb + 1, 0);
    for (int J = 0; J < nb; ++J) {
      if (rows[J].empty() || std::find(rows[J].begin(), rows[J].end(), J) == rows[J].end()) rows[J].push_back(J);
      std::sort(rows[J].begin(), rows[J].end());
      f->Ap[J + 1] = f->Ap[J] + static_cast<int>(rows[J].size());
    }
    f->Ai.resize(f->Ap[nb]);
    for (int J = 0; J < nb; ++J) std::copy(rows[J].begin(), rows[J].end(), f->Ai.begin() + f->Ap[J]);
    // Sources of each block entry's values: Bu = B(I, J) and Bl = B(J, I)ᵀ, column-major 2 × 2.
    auto source = [&](int r, int c) {  // K's value at padded (r, c): its index, nnz for 0, nnz + 1 for 1
      const int i = at[r], j = at[c];
      if (i < 0 || j < 0) return r == c ? nnz + 1 : nnz;
      const int* hit = std::lower_bound(Ki + Kp[j], Ki + Kp[j + 1], i);
      if (hit == Ki + Kp[j + 1] || *hit != i) return -1;
      return static_cast<int>(hit - Ki);
    };
    const size_t entries = f->Ai.size();
    f->upper_from.resize(4 * entries), f->lower_from.resize(4 * entries);
    for (int J = 0; J < nb; ++J)
      for (int p = f->Ap[J]; p < f->Ap[J + 1]; ++p) {
        const int I = f->Ai[p];
        for (int c = 0; c < 2; ++c)
          for (int r = 0; r < 2; ++r) {
            int u = source(2 * I + r, 2 * J + c), l = source(2 * J + c, 2 * I + r);
            // Within a block of two real equations the pattern is complete; across blocks an entry
            // missing from K's pattern is a structural zero.
            if (u < 0) u = nnz;
            if (l < 0) l = nnz;
            f->upper_from[4 * p + 2 * c + r] = u, f->lower_from[4 * p + 2 * c + r] = l;
          }
      }
    // Symbolic: elimination tree and column counts of L.
    f->parent.assign(nb, -1), f->flag.assign(nb, -1), f->Lnz.assign(nb, 0);
    for (int k = 0; k < nb; ++k) {
      f->flag[k] = k;
      for (int p = f->Ap[k]; p < f->Ap[k + 1]; ++p)
        for (int i = f->Ai[p]; i < k && f->flag[i] != k; i = f->parent[i]) {
          if (f->parent[i] == -1) f->parent[i] = k;
          ++f->Lnz[i];
          f->flag[i] = k;
        }
    }
    f->Lp.assign(nb + 1, 0);
    for (int k = 0; k < nb; ++k) f->Lp[k + 1] = f->Lp[k] + f->Lnz[k];
    f->Li.resize(f->Lp[nb]);
    f->LU.assign(8 * static_cast<size_t>(f->Lp[nb]) + 8, 0.0), f->lu_at = aligned64(f->LU);
    f->Bu.resize(4 * entries), f->Bl.resize(4 * entries);
    f->values.resize(nnz + 2);
    f->YW.assign(8 * static_cast<size_t>(nb) + 8, 0.0), f->yw_at = aligned64(f->YW);
    f->pattern.resize(nb);
    f->Dinv.resize(4 * static_cast<size_t>(nb));
    f->blocks = nb;
    simplicial_lu_ = std::move(f);
  }
  SimplicialLu& f = *simplicial_lu_;
  const int nb = f.blocks;
  std::copy(K.valuePtr(), K.valuePtr() + nnz, f.values.begin());
  f.values[nnz] = 0, f.values[nnz + 1] = 1;
  for (size_t k = 0; k < f.Bu.size(); ++k) f.Bu[k] = f.values[f.upper_from[k]], f.Bl[k] = f.values[f.lower_from[k]];
  const int* Ap = f.Ap.data();
  const int* Ai = f.Ai.data();
  const double* Bu = f.Bu.data();
  const double* Bl = f.Bl.data();
  double* __restrict Y = f.YW.data() + f.yw_at;  // Y and W interleaved: block i at 8 i and 8 i + 4
  double* __restrict W = Y + 4;
  int* __restrict Li = f.Li.data();
  double* __restrict Lx = f.LU.data() + f.lu_at;  // L and Uᵀ interleaved: entry p at 8 p and 8 p + 4
  double* __restrict Ux = Lx + 4;
  const int* Lp = f.Lp.data();
  int* Lnz = f.Lnz.data();
  const int* parent = f.parent.data();
  int* flag = f.flag.data();
  int* pattern = f.pattern.data();
  double* Dinv = f.Dinv.data();
  std::fill(f.flag.begin(), f.flag.end(), -1);
  for (int k = 0; k < nb; ++k) {
    int top = nb;
    flag[k] = k;
    Lnz[k] = 0;
    double scale[2] = {0, 0};
    for (int p = Ap[k]; p < Ap[k + 1]; ++p) {
      int i = Ai[p];
      for (int r = 0; r < 4; ++r) Y[8 * i + r] += Bu[4 * p + r];
      if (i < k)
        for (int r = 0; r < 4; ++r) W[8 * i + r] += Bl[4 * p + r];
      // Bu's column c and Bl's column c are B(:, k_c) and B(k_c, :)ᵀ.
      for (int c = 0; c < 2; ++c)
        scale[c] = std::max({scale[c], std::abs(Bu[4 * p + 2 * c]), std::abs(Bu[4 * p + 2 * c + 1]),
                             std::abs(Bl[4 * p + 2 * c]), std::abs(Bl[4 * p + 2 * c + 1])});
      int len = 0;
      for (; flag[i] != k; i = parent[i]) pattern[len++] = i, flag[i] = k;
      while (len > 0) pattern[--top] = pattern[--len];
    }
    double Dk[4];
    for (int r = 0; r < 4; ++r) Dk[r] = Y[8 * k + r], Y[8 * k + r] = 0;
    for (; top < nb; ++top) {
      const int i = pattern[top];
      double* yi = Y + 8 * i;
      double* wi = W + 8 * i;
      // yi, wi: 2 × 2 column-major. One 8-lane update per entry: (y | w) of row Li[p] −= (L | Uᵀ) blocks
      // times (y_i | w_i), the blocks' columns (columns0, columns1) against rows of y_i and w_i.
      const double y4[4] = {yi[0], yi[1], yi[2], yi[3]}, w4[4] = {wi[0], wi[1], wi[2], wi[3]};
      const V8 a = {y4[0], y4[0], y4[2], y4[2], w4[0], w4[0], w4[2], w4[2]};
      const V8 b = {y4[1], y4[1], y4[3], y4[3], w4[1], w4[1], w4[3], w4[3]};
      for (int r = 0; r < 4; ++r) yi[r] = wi[r] = 0;
      const int p2 = Lp[i] + Lnz[i];
      for (int p = Lp[i]; p < p2; ++p) {
        double* yw = Y + 8 * Li[p];
        const V8 m = load8(Lx + 8 * static_cast<size_t>(p));
        store8(yw, load8(yw) - (columns0(m) * a + columns1(m) * b));
      }
      // L(k, i) = wᵀ D_i⁻¹, U(i, k)ᵀ = yᵀ D_i⁻ᵀ; D_k −= L(k, i) y.
      const double* d = Dinv + 4 * i;
      const double l00 = w4[0] * d[0] + w4[1] * d[1], l01 = w4[0] * d[2] + w4[1] * d[3];
      const double l10 = w4[2] * d[0] + w4[3] * d[1], l11 = w4[2] * d[2] + w4[3] * d[3];
      const double u00 = d[0] * y4[0] + d[2] * y4[1], u10 = d[1] * y4[0] + d[3] * y4[1];  // U(i, k)
      const double u01 = d[0] * y4[2] + d[2] * y4[3], u11 = d[1] * y4[2] + d[3] * y4[3];
      Dk[0] -= l00 * y4[0] + l01 * y4[1];
      Dk[1] -= l10 * y4[0] + l11 * y4[1];
      Dk[2] -= l00 * y4[2] + l01 * y4[3];
      Dk[3] -= l10 * y4[2] + l11 * y4[3];
      Li[p2] = k;
      double* lx = Lx + 8 * static_cast<size_t>(p2);
      double* ux = Ux + 8 * static_cast<size_t>(p2);
      lx[0] = l00, lx[1] = l10, lx[2] = l01, lx[3] = l11;
      ux[0] = u00, ux[1] = u01, ux[2] = u10, ux[3] = u11;  // U(i, k)ᵀ
      ++Lnz[i];
    }
    // D_k = [[a, b], [c, d]] = [[1, 0], [c/a, 1]] diag(d1, d2) [[1, b/a], [0, 1]].
    const double d1 = Dk[0], d2 = Dk[3] - Dk[1] * Dk[2] / d1;
    if (!(std::abs(d1) > kTinyPivot * scale[0]) || !(std::abs(d2) > kTinyPivot * scale[1]) || !std::isfinite(d1) ||
        !std::isfinite(d2)) {
      std::fill(f.YW.begin(), f.YW.end(), 0.0);  // a later one starts clean
      return false;
    }
    const double det = d1 * d2;
    double* di = Dinv + 4 * k;
    di[0] = Dk[3] / det, di[1] = -Dk[1] / det, di[2] = -Dk[2] / det, di[3] = Dk[0] / det;
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
  char line[256];
  std::snprintf(line, sizeof line, "%s; %sUMFPACK LU, %s ordering, for non-symmetric tangents; %ld unknowns", what,
                !block_lu_ ? ""
                : uses_nested_dissection()
                    ? "2 x 2 node-block simplicial LU without pivoting on a block nested-dissection ordering, else "
                    : "2 x 2 node-block simplicial LU without pivoting on a block AMD ordering, else ",
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
  } else if (active_ == Active::simplicial_lu) {
    // x = Pᵀ U⁻¹ D⁻¹ L⁻¹ P b on a padded row-major copy (dummy rows 0), the columns together.
    const SimplicialLu& f = *simplicial_lu_;
    const Eigen::Index m = b.cols();
    work_.setZero(2 * static_cast<Eigen::Index>(f.blocks), m);
    double* Y = work_.data();
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index c = 0; c < m; ++c) Y[f.pos[i] * m + c] = b(i, c);
    for (Eigen::Index c0 = 0; c0 < m;) {  // blocks of up to 16 columns, each width at compile time
      const int w = static_cast<int>(std::min<Eigen::Index>(kMaxWidth, m - c0));
      with_width(w, [&](auto width) {
        const double* LU = f.LU.data() + f.lu_at;
        block_ldu_substitute<decltype(width)::value>(f.blocks, f.Lp.data(), f.Li.data(), LU, LU + 4, f.Dinv.data(),
                                                     Y + c0, m);
      });
      c0 += w;
    }
    x.resize(n_, m);
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index c = 0; c < m; ++c) x(i, c) = Y[f.pos[i] * m + c];
  } else if (active_ == Active::eigen) {
    // x = Pᵀ L⁻ᵀ D⁻¹ L⁻¹ P b on a row-major copy: the columns of b go through L together, so that L
    // (which does not fit in cache) is read twice per solve, not twice per column.
    const Eigen::VectorXd D = ldlt_->vectorD();
    const auto& L = ldlt_->matrixL().nestedExpression();  // strictly lower part, unit diagonal implied
    const int* Lp = L.outerIndexPtr();
    const int* Li = L.innerIndexPtr();
    const double* Lx = L.valuePtr();
    const Eigen::Index m = b.cols();
    const int* perm = P_.indices().data();
    work_.resize(n_, m);
    double* Y = work_.data();
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index c = 0; c < m; ++c) Y[perm[i] * m + c] = b(i, c);
    for (Eigen::Index c0 = 0; c0 < m; c0 += 4) {  // blocks of ≤ 4 columns: a compile-time width keeps rows in registers
      switch (std::min<Eigen::Index>(4, m - c0)) {
        case 1: ldu_substitute<1>(n_, Lp, Li, Lx, Lx, D, Y + c0, m); break;
        case 2: ldu_substitute<2>(n_, Lp, Li, Lx, Lx, D, Y + c0, m); break;
        case 3: ldu_substitute<3>(n_, Lp, Li, Lx, Lx, D, Y + c0, m); break;
        default: ldu_substitute<4>(n_, Lp, Li, Lx, Lx, D, Y + c0, m); break;
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
