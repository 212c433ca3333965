// The paper's generated uniaxial case (issue 2): a Q8 strip of ~2200 dofs, clamped grip, free side,
// 35 displacement steps to 100 % strain with the Mooney–Rivlin law. Target: ≤ 100 ms, and at most
// twice the time of its own factorizations. Counters: dofs, Newton iterations, factorizations and the
// share of the run's time in factorizations.
#include <benchmark/benchmark.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>

#include "assembly.hpp"       // the engine's private assembly (bench/CMakeLists.txt adds src/fem)
#include "linear_solver.hpp"  // and its sparse solver
#include "simulation_timing.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/solver.hpp"

namespace {

using namespace tricot::fem;

TestModel uniaxial_strip(ElementType type, int nx, int ny) {
  MeshOptions m;
  m.width = 10, m.height = 50, m.nx = nx, m.ny = ny, m.type = type;
  TestModel t;
  t.name = "uniaxial";
  t.mesh = make_quarter_mesh(m);
  for (int k = 1; k <= 35; ++k) t.loads.push_back(m.height * k / 35.0);  // 2d/(2H) = 100 % at the end
  return t;
}

void run(benchmark::State& state, const TestModel& t, const SolveOptions& o) {
  tricot::bench::time_simulation(state, t, MooneyRivlin(paper_mooney_rivlin_terms()), o);
}

SolveOptions options(bool sensitivities = false, LinearSolverKind kind = LinearSolverKind::eigen_ldlt) {
  SolveOptions o;
  o.sensitivities = sensitivities;
  o.linear_solver = kind;
  return o;
}

// What simulate() does by default (Eigen's SimplicialLDLT), with and without sensitivities.
void BM_UniaxialMooneyQ8(benchmark::State& state) { run(state, uniaxial_strip(ElementType::Q8, 8, 42), options()); }
void BM_UniaxialMooneyQ8Sensitivities(benchmark::State& state) {
  run(state, uniaxial_strip(ElementType::Q8, 8, 42), options(true));
}
// The alternative: CHOLMOD instead of Eigen.
void BM_UniaxialMooneyQ8Cholmod(benchmark::State& state) {
  run(state, uniaxial_strip(ElementType::Q8, 8, 42), options(false, LinearSolverKind::cholmod_ldlt));
}

// The pieces of one Newton iteration on the same strip, at the last step's converged state: one
// assembly with and without the tangent, and one numeric factorization with each candidate solver
// (the symbolic analysis is done once, outside the timing, as in simulate()).
struct Pieces {
  TestModel t = uniaxial_strip(ElementType::Q8, 8, 42);
  MooneyRivlin law{paper_mooney_rivlin_terms()};
  detail::DofMap dofs = detail::make_dof_map(t);
  detail::Assembler assembler{t, dofs, law};
  Eigen::VectorXd u;
  detail::Assembled a;
  Pieces() {
    u = simulate(t, law).steps.back().u;
    assembler.assemble(u, {true, false}, a);
  }
};
const Pieces& pieces() {
  static const Pieces p;
  return p;
}

void BM_AssemblyQ8(benchmark::State& state) {
  const Pieces& p = pieces();
  detail::Assembled a;
  for (auto _ : state) p.assembler.assemble(p.u, {state.range(0) == 1, false}, a);
  state.SetLabel(state.range(0) == 1 ? "residual and tangent" : "residual only");
}

template <class Solver>
void factorize_loop(benchmark::State& state, Solver& s, const Eigen::SparseMatrix<double>& K) {
  s.analyzePattern(K);
  for (auto _ : state) s.factorize(K);
  if (s.info() != Eigen::Success) state.SkipWithError("factorization failed");
  state.counters["n"] = static_cast<double>(K.rows());
}

void BM_FactorizeCholmodSimplicialLDLt(benchmark::State& state) {  // LinearSolverKind::cholmod_ldlt
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> s;
  s.setMode(Eigen::CholmodLDLt);
  s.cholmod().print = 0;
  const Eigen::SparseMatrix<double> L = pieces().a.K.triangularView<Eigen::Lower>();
  factorize_loop(state, s, L);
}
void BM_FactorizeCholmodSupernodalLLt(benchmark::State& state) {
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> s;
  s.setMode(Eigen::CholmodSupernodalLLt);
  s.cholmod().print = 0;
  const Eigen::SparseMatrix<double> L = pieces().a.K.triangularView<Eigen::Lower>();
  factorize_loop(state, s, L);
}
void BM_FactorizeEigenSimplicialLDLT(benchmark::State& state) {  // Eigen with its own AMD, a permuted copy per call
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> s;
  factorize_loop(state, s, pieces().a.K);
}
// What simulate() uses (LinearSolverKind::eigen_ldlt): AMD once, P K Pᵀ filled through a map, factorized in place.
void BM_FactorizeEngineEigenLDLt(benchmark::State& state) {
  const auto& K = pieces().a.K;
  detail::LinearSolver s(K, LinearSolverKind::eigen_ldlt);
  for (auto _ : state) benchmark::DoNotOptimize(s.factorize(K, true));
  state.counters["n"] = static_cast<double>(K.rows());
}
// One back-substitution with that factorization, and one product with K.
void BM_SolveEngineEigenLDLt(benchmark::State& state) {
  const auto& K = pieces().a.K;
  detail::LinearSolver s(K, LinearSolverKind::eigen_ldlt);
  s.factorize(K, true);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Ones(K.rows(), 1);
  Eigen::MatrixXd x;
  for (auto _ : state) s.solve(b, x);
}
void BM_ProductWithK(benchmark::State& state) {
  const auto& K = pieces().a.K;
  const Eigen::MatrixXd b = Eigen::MatrixXd::Ones(K.rows(), 1);
  Eigen::MatrixXd x;
  for (auto _ : state) x.noalias() = K * b;
}

}  // namespace

// Issue 28, no loss at scale: one identification evaluation (5 steps to 40 % with the sensitivities
// of the 4 Mooney–Rivlin coefficients) of a full clamped square at about 25 000 dofs, meshed in T6
// (55 × 55 cells split in two) or Q8 (64 × 64): the time per dof of each element type (counter
// ns_per_dof). Named conditions: the bottom clamped, the top pulled and held across.
void BM_EvaluationPerDof(benchmark::State& state) {
  const auto type = static_cast<ElementType>(state.range(0));
  const int n = type == ElementType::T6 ? 55 : 64;
  MeshOptions m;
  m.width = m.height = 100, m.nx = m.ny = n, m.type = type;
  TestModel t;
  t.name = "square";
  t.mesh = make_quarter_mesh(m);
  t.loads = {1, 2, 3, 4, 5};
  std::vector<double> pull;
  for (int k = 1; k <= 5; ++k) pull.push_back(40.0 * k / 5);
  t.conditions = {{"bottom", 0, {}}, {"bottom", 1, {}}, {"top", 0, {}}, {"top", 1, pull}};
  t.force_boundary = "top";
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  SolveOptions o;
  o.sensitivities = true;
  double seconds = 0;
  for (auto _ : state) {
    const SimulationResult r = simulate(t, law, o);
    if (!r.usable()) state.SkipWithError(r.message.c_str());
    seconds += r.seconds;
  }
  state.counters["dofs"] = t.mesh.dofs();
  state.counters["us_per_dof"] = 1e6 * seconds / double(state.iterations()) / t.mesh.dofs();
}
BENCHMARK(BM_EvaluationPerDof)
    ->Arg(static_cast<int>(ElementType::T6))
    ->Arg(static_cast<int>(ElementType::Q8))
    ->Unit(benchmark::kMillisecond);

BENCHMARK(BM_AssemblyQ8)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FactorizeCholmodSimplicialLDLt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FactorizeCholmodSupernodalLLt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FactorizeEigenSimplicialLDLT)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FactorizeEngineEigenLDLt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SolveEngineEigenLDLt)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ProductWithK)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_UniaxialMooneyQ8)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UniaxialMooneyQ8Sensitivities)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UniaxialMooneyQ8Cholmod)->Unit(benchmark::kMillisecond);
