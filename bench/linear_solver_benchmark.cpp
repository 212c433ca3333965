// Issue 15: the sparse direct solvers on real FE tangents of the clamped Mooney–Rivlin strip
// (examples/uniaxial-mooney: quarter 25 × 100 mm, Q8, ny = 3.4 nx) from ~2 200 to ~520 000 dofs.
// Each iteration is one numeric factorization and one solve with one right-hand side; the ordering
// and symbolic analysis are done once, outside the timing, as in simulate(). The tangent is the one at
// a 10 % affine stretch (u_y = 0.1 Y), which meets every boundary condition of the clamped strip.
// Argument: nx (10, 20, 30, 40, 80, 160 → 2 087 … 523 007 unknowns). Counter n = unknowns (free dofs).
// The exponent is fitted in docs/validation.md §7.
#include <benchmark/benchmark.h>

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>
#include <map>
#include <memory>

#include "assembly.hpp"       // the engine's private assembly (bench/CMakeLists.txt adds src/fem)
#include "linear_solver.hpp"  // and its sparse solver
#include "simulation_timing.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/rig.hpp"

namespace {

using namespace tricot::fem;
using SpMat = Eigen::SparseMatrix<double>;

constexpr double kStretch = 0.1;  // u_y = kStretch · Y: a deformed state, far from any instability

TestModel clamped_strip(int nx) {
  MeshOptions m;
  m.width = 25, m.height = 100, m.nx = nx, m.ny = nx * 34 / 10, m.type = ElementType::Q8;
  TestModel t;
  t.name = "tension";
  t.mesh = make_quarter_mesh(m);
  t.grip_holds_x = true;
  t.loads = {kStretch * m.height};
  return t;
}

// The free-free tangent of the strip with nx elements across, built once per size.
const SpMat& tangent(int nx) {
  static std::map<int, std::unique_ptr<SpMat>> cache;
  auto& slot = cache[nx];
  if (!slot) {
    const TestModel t = clamped_strip(nx);
    const MooneyRivlin law(paper_mooney_rivlin_terms());
    const detail::DofMap dofs = detail::make_dof_map(t);
    const detail::Assembler assembler(t, dofs, law);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(t.mesh.dofs());
    for (int n = 0; n < t.mesh.nodes(); ++n) u(2 * n + 1) = kStretch * t.mesh.X(1, n);
    detail::Assembled a;
    assembler.assemble(u, {true, false}, a);
    slot = std::make_unique<SpMat>(a.K);
  }
  return *slot;
}

template <class Solver>
void factorize_and_solve(benchmark::State& state, Solver& s, const SpMat& K) {
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(K.rows());
  Eigen::VectorXd x;
  s.analyzePattern(K);
  for (auto _ : state) {
    s.factorize(K);
    x = s.solve(b);
    benchmark::DoNotOptimize(x.data());
  }
  if (s.info() != Eigen::Success) state.SkipWithError("factorization failed");
  state.counters["n"] = static_cast<double>(K.rows());
}

// The engine's solver: one numeric factorization (symmetric or not) and one solve per iteration.
void factorize_and_solve(benchmark::State& state, detail::LinearSolver& s, const SpMat& K, bool symmetric) {
  const Eigen::MatrixXd b = Eigen::MatrixXd::Ones(K.rows(), 1);
  Eigen::MatrixXd x;
  for (auto _ : state) {
    if (!s.factorize(K, symmetric)) state.SkipWithError("factorization failed");
    s.solve(b, x);
  }
  state.counters["n"] = static_cast<double>(K.rows());
}

// What simulate() did before issue 15 (LinearSolverKind::eigen_ldlt): AMD once, Eigen's simplicial
// LDLᵀ in place.
void BM_EigenSimplicialLdltAmd(benchmark::State& state) {
  const SpMat& K = tangent(static_cast<int>(state.range(0)));
  detail::LinearSolver s(K, LinearSolverKind::eigen_ldlt);
  factorize_and_solve(state, s, K, true);
}

// CHOLMOD's supernodal LLᵀ (BLAS on the supernodes) with a given ordering; -1: CHOLMOD's default
// choice (AMD, then METIS if AMD's fill is high).
void cholmod_supernodal(benchmark::State& state, int ordering) {
  const SpMat L = tangent(static_cast<int>(state.range(0))).triangularView<Eigen::Lower>();
  Eigen::CholmodDecomposition<SpMat, Eigen::Lower> s;
  s.setMode(Eigen::CholmodSupernodalLLt);
  s.cholmod().print = 0;
  if (ordering >= 0) {
    s.cholmod().nmethods = 1;
    s.cholmod().method[0].ordering = ordering;
    s.cholmod().postorder = 1;
  }
  factorize_and_solve(state, s, L);
}
void BM_CholmodSupernodalDefault(benchmark::State& state) { cholmod_supernodal(state, -1); }
void BM_CholmodSupernodalAmd(benchmark::State& state) { cholmod_supernodal(state, CHOLMOD_AMD); }
void BM_CholmodSupernodalMetis(benchmark::State& state) { cholmod_supernodal(state, CHOLMOD_METIS); }
void BM_CholmodSupernodalNesdis(benchmark::State& state) { cholmod_supernodal(state, CHOLMOD_NESDIS); }

// The engine's own choice (LinearSolverKind::automatic), as simulate() uses it.
void BM_EngineAutomatic(benchmark::State& state) {
  const SpMat& K = tangent(static_cast<int>(state.range(0)));
  detail::LinearSolver s(K, LinearSolverKind::automatic);
  factorize_and_solve(state, s, K, true);
  state.SetLabel(s.description());
}

// UMFPACK LU, the path of non-symmetric tangents (response-surface law); the clamped strip's tangent
// stands in for one (same pattern, same size), with UMFPACK's default ordering and with METIS.
void umfpack(benchmark::State& state, int ordering) {
  const SpMat& K = tangent(static_cast<int>(state.range(0)));
  Eigen::UmfPackLU<SpMat> s;
  s.umfpackControl()(UMFPACK_IRSTEP) = 0;
  if (ordering >= 0) s.umfpackControl()(UMFPACK_ORDERING) = ordering;
  factorize_and_solve(state, s, K);
}
void BM_UmfpackDefault(benchmark::State& state) { umfpack(state, -1); }
void BM_UmfpackMetis(benchmark::State& state) { umfpack(state, UMFPACK_ORDERING_METIS); }

// One forward solve of the clamped strip, 10 displacement steps to 100 % strain (the case file's
// load_max = 100 mm), with the pre-issue-15 solver (second argument 1: eigen_ldlt) or the engine's
// choice (0: automatic). Counters: simulation_timing.hpp.
void BM_ForwardSolve(benchmark::State& state) {
  TestModel t = clamped_strip(static_cast<int>(state.range(0)));
  t.loads.clear();
  for (int k = 1; k <= 10; ++k) t.loads.push_back(10.0 * k);
  SolveOptions o;
  o.linear_solver = state.range(1) == 1 ? LinearSolverKind::eigen_ldlt : LinearSolverKind::automatic;
  tricot::bench::time_simulation(state, t, MooneyRivlin(paper_mooney_rivlin_terms()), o);
}

// The §4 knit campaign's coarse model (fem::make_rig_test: 110 mm, 12 × 10 Q8, guides and clips
// tied, 810 unknowns): its tangent at a 10 % affine pull (Mooney–Rivlin stands in for the response
// surface: same pattern), factorized by the simplicial LU without pivoting that non-symmetric tangents
// take (LinearSolverKind::eigen_ldlt), then (BM_SimplicialLuRigSolve) solved for 1 or 14 columns (the
// sensitivities'), and (BM_RigResidual) b − K x (the refinement's residual). Counter nnz_LU: L + U + D.
struct RigTangent {
  TestModel test;
  SpMat K;
};
const RigTangent& rig_tangent(int nx = 12, int ny = 10) {
  static std::map<std::pair<int, int>, std::unique_ptr<RigTangent>> cache;
  auto& slot = cache[{nx, ny}];
  if (!slot) {
    slot = std::make_unique<RigTangent>();
    RigTangent& t = *slot;
    RigOptions o;
    o.transverse_strain = 0.2;
    o.nx = nx, o.ny = ny;
    t.test = make_rig_test(o);
    const MooneyRivlin law(paper_mooney_rivlin_terms());
    const detail::DofMap dofs = detail::make_dof_map(t.test);
    const detail::Assembler assembler(t.test, dofs, law);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(t.test.mesh.dofs());
    for (int n = 0; n < t.test.mesh.nodes(); ++n) u(2 * n + 1) = kStretch * t.test.mesh.X(1, n);
    detail::Assembled a;
    assembler.assemble(u, {true, false}, a);
    t.K = a.K;
  }
  return *slot;
}

// The rig's tangent on finer meshes (nx × ny: 12 × 10, 24 × 20 the campaign's synthesis, 70 × 58 the
// paper's ~24 000 dofs), factorized as a non-symmetric tangent by the block LU (third argument 0: its
// ordering by the size) or by UMFPACK (1; METIS from LinearSolver::kLuMetisFrom unknowns, AMD below),
// plus one solve: where the crossover between them lies. 2 and 3: the block LU on AMD and on nested
// dissection whatever the size, where LinearSolver::kNestedDissectionFrom/Below lie.
void BM_RigLu(benchmark::State& state) {
  const SpMat& K = rig_tangent(static_cast<int>(state.range(0)), static_cast<int>(state.range(1))).K;
  const int64_t how = state.range(2);
  detail::LinearSolver s(K, how == 1 ? LinearSolverKind::cholmod_ldlt : LinearSolverKind::eigen_ldlt);
  using Ordering = detail::LinearSolver::BlockOrdering;
  s.block_ordering = how == 2 ? Ordering::amd : how == 3 ? Ordering::nested_dissection : Ordering::by_size;
  factorize_and_solve(state, s, K, false);
  state.counters["fallbacks"] = s.simplicial_lu_fallbacks;
  state.counters["nnz_LU"] = static_cast<double>(s.lu_nonzeros());
  const char* label[] = {"block LU", "UMFPACK", "block LU, AMD", "block LU, nested dissection"};
  state.SetLabel(label[how]);
}

void BM_SimplicialLuRig(benchmark::State& state) {
  const SpMat& K = rig_tangent().K;
  detail::LinearSolver s(K, LinearSolverKind::eigen_ldlt);
  for (auto _ : state)
    if (!s.factorize(K, false)) state.SkipWithError("factorization failed");
  state.counters["n"] = static_cast<double>(K.rows());
  state.counters["nnz_K"] = static_cast<double>(K.nonZeros());
  state.counters["nnz_LU"] = static_cast<double>(s.lu_nonzeros());
}

void BM_SimplicialLuRigSolve(benchmark::State& state) {
  const SpMat& K = state.range(1) > 0
                       ? rig_tangent(static_cast<int>(state.range(1)), static_cast<int>(state.range(2))).K
                       : rig_tangent().K;
  detail::LinearSolver s(K, LinearSolverKind::eigen_ldlt);
  if (!s.factorize(K, false)) state.SkipWithError("factorization failed");
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(K.rows(), state.range(0));
  Eigen::MatrixXd x, r;
  for (auto _ : state) {
    s.solve(b, x);
    benchmark::DoNotOptimize(x.data());
  }
  r.noalias() = b - K * x;
  state.counters["residual"] = r.norm() / b.norm();
}

// The refinement's residual b − K x for 1 or 14 columns on the same tangent.
void BM_RigResidual(benchmark::State& state) {
  const SpMat& K = state.range(1) > 0
                       ? rig_tangent(static_cast<int>(state.range(1)), static_cast<int>(state.range(2))).K
                       : rig_tangent().K;
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(K.rows(), state.range(0));
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(K.rows(), state.range(0));
  Eigen::MatrixXd r;
  for (auto _ : state) {
    detail::residual(K, b, x, r);
    benchmark::DoNotOptimize(r.data());
  }
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int nx : {10, 20, 30, 40, 80, 160}) b->Arg(nx);
  b->Unit(benchmark::kMillisecond);
}

}  // namespace

BENCHMARK(BM_EigenSimplicialLdltAmd)->Apply(sizes);
BENCHMARK(BM_CholmodSupernodalDefault)->Apply(sizes);
BENCHMARK(BM_CholmodSupernodalAmd)->Apply(sizes);
BENCHMARK(BM_CholmodSupernodalMetis)->Apply(sizes);
BENCHMARK(BM_CholmodSupernodalNesdis)->Apply(sizes);
BENCHMARK(BM_EngineAutomatic)->Apply(sizes);
BENCHMARK(BM_UmfpackDefault)->Apply(sizes);
BENCHMARK(BM_UmfpackMetis)->Apply(sizes);
BENCHMARK(BM_SimplicialLuRig)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SimplicialLuRigSolve)
    ->Args({1, 0, 0})
    ->Args({14, 0, 0})
    ->Args({14, 24, 20})
    ->Args({14, 70, 58})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RigResidual)
    ->Args({1, 0, 0})
    ->Args({14, 0, 0})
    ->Args({14, 24, 20})
    ->Args({14, 70, 58})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RigLu)
    ->ArgsProduct({{12}, {10}, {0, 1}})
    ->Args({24, 20, 0})
    ->Args({24, 20, 1})
    ->Args({70, 58, 0})
    ->Args({70, 58, 1})
    ->Args({100, 84, 0})
    ->Args({100, 84, 1})
    ->Apply([](benchmark::internal::Benchmark* b) {
      for (const auto& [nx, ny] : {std::pair{12, 10}, {24, 20}, {40, 34}, {70, 58}, {92, 76}, {108, 90}})
        b->Args({nx, ny, 2})->Args({nx, ny, 3});
    })
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ForwardSolve)->ArgsProduct({{10, 20, 40, 80, 160}, {0, 1}})->Unit(benchmark::kMillisecond);
