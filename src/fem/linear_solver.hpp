// Sparse direct solution of the free-free tangent (docs/theory.md §4, §7), private to fem. Symmetric tangents:
// LDLᵀ without pivoting, by Eigen's SimplicialLDLT or CHOLMOD's simplicial LDLᵀ, or CHOLMOD's
// supernodal LLᵀ on a METIS ordering (falling back to CHOLMOD's LDLᵀ when the tangent is not positive
// definite); SolveOptions::linear_solver picks one, or lets the size pick (LinearSolverKind::automatic,
// crossover measured in bench/linear_solver_benchmark.cpp). Non-symmetric tangents: with the Eigen
// backend, and under `automatic` below kBlockLuBelow unknowns, a simplicial LU without pivoting on 2 × 2
// node blocks, ordered by blocks (AMD, or nested dissection at mid sizes; the tangent's pattern is
// symmetric, so L and Uᵀ have the block LDLᵀ's pattern); UMFPACK LU for the larger ones, with an
// explicit CHOLMOD kind, where a pivot of that LU is tiny, or where LDLᵀ breaks down.
// The ordering and symbolic analysis are done once per simulation (the pattern is fixed); each
// factorization is numeric only, and the matrix handed to it is filled through a precomputed map.
#pragma once

#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/UmfPackSupport>
#include <memory>
#include <string>
#include <vector>

#include "tricot/fem/solver.hpp"

namespace tricot::fem::detail {

/// r = b − K x (b, x: n × m). Several columns go through K together (row-major copies: each of K's
/// entries updates a row of r), not column by column.
void residual(const Eigen::SparseMatrix<double>& K, const Eigen::MatrixXd& b, const Eigen::MatrixXd& x,
              Eigen::MatrixXd& r);

class LinearSolver {
 public:
  /// Tangents of at least this many unknowns go to CHOLMOD's supernodal LLᵀ under
  /// LinearSolverKind::automatic; smaller ones to Eigen's SimplicialLDLT. The crossover measured on
  /// the clamped strip (bench/linear_solver_benchmark.cpp, docs/validation.md §7).
  static constexpr Eigen::Index kSupernodalFrom = 20000;
  /// Non-symmetric tangents of at least this many unknowns are ordered by METIS in UMFPACK (its
  /// default, AMD, below).
  static constexpr Eigen::Index kLuMetisFrom = 20000;
  /// Under LinearSolverKind::automatic, non-symmetric tangents below this many unknowns go to the block
  /// LU (factorize_simplicial_lu), larger ones to UMFPACK: on the rig's tangent the block LU with one
  /// solve took 1.4 / 65 / 152 ms against UMFPACK's 12 / 205 / 619 ms at 2 919 / 24 475 / 50 567 unknowns
  /// (bench/linear_solver_benchmark.cpp, BM_RigLu); not measured beyond.
  static constexpr Eigen::Index kBlockLuBelow = 60000;
  /// The block LU orders its blocks by nested dissection (CHOLMOD's: METIS bisections, CAMD on the
  /// parts) from kNestedDissectionFrom to below kNestedDissectionBelow unknowns, by AMD elsewhere. On
  /// the rig's tangent (BM_RigLu/nx/ny/{2: AMD, 3: nested dissection}) nested dissection's
  /// factorization took 5–27 % less time from 8 227 to 35 839 unknowns (24 475: 3.8e7 block updates
  /// against 5.7e7, 44 ms against 57 ms), within ±10 % of AMD's at 42 103, and 5–27 % more from
  /// 50 567; at 739 and 2 919 the two are alike, and nested dissection costs more to compute.
  static constexpr Eigen::Index kNestedDissectionFrom = 5000;
  static constexpr Eigen::Index kNestedDissectionBelow = 40000;
  static bool nested_dissection(Eigen::Index n) { return n >= kNestedDissectionFrom && n < kNestedDissectionBelow; }
  /// The block LU's ordering: by the size (nested_dissection), or one of them whatever the size (for
  /// the benchmark that measures the crossover). Set before the first factorization.
  enum class BlockOrdering { by_size, amd, nested_dissection };
  BlockOrdering block_ordering = BlockOrdering::by_size;
  /// The sensitivities factorize (prefers_factorization) below this many unknowns: on the rig's
  /// tangent a factorization costs ~1.05 refinement sweeps of 14 columns at 739 unknowns, ~1.8 at
  /// 2 919 (break-even with the predictor's sweep it saves), ~4.2 at 24 475 (BM_RigLu,
  /// BM_SimplicialLuRigSolve, BM_RigResidual).
  static constexpr Eigen::Index kFactorizeColumnsBelow = kSensitivitiesAfterBelow;

  /// For the (full, symmetric) pattern: the backend, its ordering and symbolic analysis (the symmetric
  /// backend's at the first symmetric tangent, the block LU's at the first non-symmetric one).
  LinearSolver(const Eigen::SparseMatrix<double>& pattern, LinearSolverKind kind);
  /// Numeric factorization of K (same pattern as at construction): LDLᵀ when `symmetric` (K's
  /// lower triangle is read), else or on a zero pivot LU. False when both fail (singular tangent).
  bool factorize(const Eigen::SparseMatrix<double>& K, bool symmetric);
  /// x = K⁻¹ b with the last factorization (b may have several columns; x may not alias b).
  void solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) const;

  /// Whether `columns` right-hand sides with a nearby tangent (e.g. the converged state's, after the
  /// last Newton iterate's factorization) cost less through a factorization of that tangent than through
  /// iterative refinement on the current factorization (~2 sweeps, each a solve and a product with K,
  /// and another refined solve for the next predictor). True only for the simplicial block LU, from 8
  /// columns, below kFactorizeColumnsBelow unknowns: on the 810-dof rig tangent its factorization costs
  /// ~153 us against ~146 us per sweep of 14 columns (bench/linear_solver_benchmark.cpp,
  /// BM_SimplicialLuRig*, BM_RigResidual). LDLᵀ, CHOLMOD and UMFPACK factorizations cost many sweeps.
  bool prefers_factorization(Eigen::Index columns) const {
    return active_ == Active::simplicial_lu && columns >= 8 && n_ < kFactorizeColumnsBelow;
  }

  /// The backend in use for symmetric tangents (never `automatic`).
  LinearSolverKind kind() const { return kind_; }
  /// One line naming the factorization, its ordering and the size, e.g. for a --verbose log.
  std::string description() const;
  /// Entries of the simplicial LU's L, U and D (its 2 × 2 blocks, padding included) after its first
  /// factorization (else 0), for benchmarks.
  Eigen::Index lu_nonzeros() const {
    return simplicial_lu_ ? 8 * static_cast<Eigen::Index>(simplicial_lu_->Lp.back()) + 4 * simplicial_lu_->blocks : 0;
  }

  double seconds = 0;  ///< wall time in numeric factorizations
  int factorizations = 0;
  int ldlt_fallbacks = 0;           ///< supernodal LLᵀ factorizations that met a non-positive pivot (then LDLᵀ)
  int lu_fallbacks = 0;             ///< symmetric tangents that LDLᵀ could not factorize (then LU)
  int simplicial_lu_fallbacks = 0;  ///< non-symmetric tangents whose simplicial LU met a tiny pivot (then UMFPACK)

 private:
  using Ldlt = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper, Eigen::NaturalOrdering<int>>;
  using Cholmod = Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>;
  LinearSolverKind kind_;
  Eigen::Index n_ = 0;
  bool block_lu_ = false;  ///< non-symmetric tangents try the block LU first (else UMFPACK directly)
  bool uses_nested_dissection() const {
    return block_ordering == BlockOrdering::by_size ? nested_dissection(n_)
                                                    : block_ordering == BlockOrdering::nested_dissection;
  }
  /// The symmetric backend's ordering and symbolic analysis, at the first symmetric tangent (a law
  /// whose tangents are never symmetric, e.g. the response surface, never pays for it).
  void analyze_symmetric(const Eigen::SparseMatrix<double>& pattern);
  /// The triangle the LDLᵀ backend reads: Eigen: the upper triangle of P K Pᵀ (AMD ordering P);
  /// CHOLMOD: K's lower triangle (CHOLMOD orders it itself). tri_.valuePtr()[k] = K.valuePtr()[from_[k]].
  Eigen::SparseMatrix<double> tri_;
  std::vector<int> from_;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P_, Pinv_;
  std::unique_ptr<Ldlt> ldlt_;
  std::unique_ptr<Cholmod> cholmod_;
  /// cholmod_supernodal only: the simplicial LDLᵀ for tangents that are not positive definite,
  /// analyzed at its first use (same ordering method as cholmod_).
  std::unique_ptr<Cholmod> cholmod_ldlt_;
  std::unique_ptr<Eigen::UmfPackLU<Eigen::SparseMatrix<double>>> lu_;
  /// The simplicial LU (eigen_ldlt, or automatic below kBlockLuBelow unknowns), built at the first
  /// non-symmetric tangent, on 2 × 2 node
  /// blocks: consecutive equations with the same pattern (a node's two free dofs) form a block, any other
  /// equation a block of its own with a decoupled dummy unknown beside it (identity row and column:
  /// exact zeros everywhere else, so the real unknowns' factors are those of the scalar LU). Blocks are
  /// ordered by AMD on the block pattern; B = P K Pᵀ (padded) = L D U, L and Uᵀ block unit lower
  /// triangular with the pattern of the block LDLᵀ's L (CSC: Lp, Li), D block diagonal. Entry p's 2 × 2
  /// blocks L(R, I) and U(I, R)ᵀ, each column-major (m00 m10 m01 m11), share a cache line in LU (at
  /// lu_at + 8 p and + 4); the row solves' y and w likewise in YW.
  /// Dinv: D's 2 × 2 inverses (column-major). False on a tiny pivot of D's scalar LDU (then UMFPACK).
  bool factorize_simplicial_lu(const Eigen::SparseMatrix<double>& K);
  struct SimplicialLu {
    int blocks = 0;
    std::vector<int> pos;                     // equation → its row in the padded, permuted system (2 · block + slot)
    std::vector<int> Ap, Ai;                  // B's upper block triangle by block columns
    std::vector<int> upper_from, lower_from;  // per block entry 4 sources in K's values (nnz: 0, nnz + 1: 1)
    std::vector<int> parent, Lp, Li, Lnz, flag, pattern;  // elimination tree, L's block columns, workspace
    std::vector<double> values, LU, Bu, Bl, YW, Dinv;
    size_t lu_at = 0, yw_at = 0;  // 64-byte aligned starts in LU and YW
  };
  std::unique_ptr<SimplicialLu> simplicial_lu_;
  /// UMFPACK's factors P K Q = L U (no row scaling), taken out of its Numeric object at the first
  /// multi-column solve after a factorization: its own solve goes column by column, each reading the
  /// factors again; here the columns go through L (by rows) and U (by columns) together.
  void solve_lu_columns(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) const;
  enum class Active { none, eigen, cholmod, cholmod_ldlt, simplicial_lu, lu };
  Active active_ = Active::none;
  mutable Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> work_;
};

}  // namespace tricot::fem::detail
