// Cost of the identification's building blocks on the paper's uniaxial Mooney–Rivlin problem
// (§3.3: 2200 dofs, 35 steps): one forward solve, one objective + Jacobian evaluation with exact
// sensitivities (docs/theory.md §7) or finite differences (the paper's way), and a whole identification.
// Counter `x_forward`: the evaluation's time as a multiple of one forward solve.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/identify.hpp"
#include "tricot/ident/objective.hpp"
#include "tricot/ident/synthetic.hpp"

namespace {

using namespace tricot;

// The `uniaxial-mooney` example's strip (quarter 25 × 100 mm, Q8 10 × 34 = 2218 dofs), clamped,
// pulled by a force up to 20 N (λ ≈ 1.9) in 35 steps: the paper's edge-displacement test.
fem::TestModel strip(int nx, int ny) {
  fem::MeshOptions m;
  m.width = 25, m.height = 100, m.nx = nx, m.ny = ny, m.type = fem::ElementType::Q8;
  fem::TestModel t;
  t.name = "tension";
  t.mesh = fem::make_quarter_mesh(m);
  t.control = fem::GripControl::force;
  for (int k = 1; k <= 35; ++k) t.loads.push_back(20.0 * k / 35);
  return t;
}

struct Setup {
  fem::TestModel model = strip(10, 34);
  std::vector<fem::MooneyRivlinTerm> truth = fem::paper_mooney_rivlin_terms();
  ident::Experiment data;
  std::unique_ptr<ident::Objective> objective;
  Eigen::VectorXd J;

  Setup() {
    // Data from a finer mesh; 7 × 20 points over the quarter.
    const fem::TestModel fine = strip(20, 68);
    const fem::SimulationResult sim = fem::simulate(fine, fem::MooneyRivlin(truth));
    Eigen::Matrix2Xd points(2, 140);
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 7; ++i) points.col(j * 7 + i) = Vec2(1 + 20.0 * i / 6, 1 + 90.0 * j / 19);
    data.tests.push_back(ident::measure(fine, sim, points));
    std::vector<ident::Parameter> p;
    for (const auto& t : truth) p.push_back({"C" + std::to_string(t.i) + std::to_string(t.j), 0.9 * t.C});
    objective =
        std::make_unique<ident::Objective>(std::vector<fem::TestModel>{model}, data, fem::MooneyRivlin(truth), p);
    J = Eigen::Vector4d(0.9 * truth[0].C, 0.9 * truth[1].C, 0.9 * truth[2].C, 0.9 * truth[3].C);
  }
};

Setup& setup() {
  static Setup s;
  return s;
}

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
// Process CPU time (all threads): the ratios below then hold on a machine busy with other work.
double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

void BM_ForwardSolve(benchmark::State& state) {
  Setup& s = setup();
  const fem::MooneyRivlin law(s.truth);
  for (auto _ : state) benchmark::DoNotOptimize(fem::simulate(s.model, law));
  state.counters["dofs"] = s.model.mesh.dofs();
}
BENCHMARK(BM_ForwardSolve)->Unit(benchmark::kMillisecond)->UseRealTime();

// Each iteration times one forward solve and then the evaluation; `x_forward` is the ratio of
// their CPU times (robust to other load on the machine), the reported time the evaluation's wall.
void BM_ObjectiveAndJacobian(benchmark::State& state) {
  Setup& s = setup();
  const fem::MooneyRivlin law(s.truth);
  ident::JacobianOptions o;
  o.mode = state.range(0) == 0 ? ident::JacobianMode::exact : ident::JacobianMode::finite_difference;
  o.difference = state.range(0) == 2 ? ident::Difference::central : ident::Difference::forward;
  o.threads = 1;  // the cost per evaluation; columns in parallel divide the wall time by the threads
  double forward = 0, evaluation = 0;
  for (auto _ : state) {
    double c0 = cpu_seconds();
    benchmark::DoNotOptimize(fem::simulate(s.model, law));
    forward += cpu_seconds() - c0;
    const auto t0 = Clock::now();
    c0 = cpu_seconds();
    benchmark::DoNotOptimize(ident::evaluate(*s.objective, s.J, true, o));
    evaluation += cpu_seconds() - c0;
    state.SetIterationTime(since(t0));
  }
  state.counters["x_forward"] = evaluation / forward;
  state.counters["dofs"] = s.model.mesh.dofs();
  state.SetLabel(state.range(0) == 0 ? "exact" : state.range(0) == 1 ? "fd_forward" : "fd_central");
}
BENCHMARK(BM_ObjectiveAndJacobian)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseManualTime();

// The both-data identification (edge displacement + field) from 0.5 × the truth.
void BM_Identify(benchmark::State& state) {
  Setup& s = setup();
  std::vector<ident::Parameter> p;
  for (const auto& t : s.truth) p.push_back({"C" + std::to_string(t.i) + std::to_string(t.j), 0.5 * t.C});
  const ident::Objective objective({s.model}, s.data, fem::MooneyRivlin(s.truth), p);
  ident::IdentifyOptions o;
  o.jacobian = state.range(0) == 0 ? ident::JacobianMode::exact : ident::JacobianMode::finite_difference;
  ident::IdentifyResult r;
  double cpu = 0;
  for (auto _ : state) {
    const double c0 = cpu_seconds();
    r = ident::identify(objective, o);
    cpu = cpu_seconds() - c0;
  }
  state.counters["cpu_s"] = cpu;
  state.counters["wall_s"] = r.wall_seconds;
  state.counters["iterations"] = r.iterations;
  state.counters["evaluations"] = r.evaluations;
  double worst = 0;  // over C10, C20, C21
  for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(r.parameters(k) / s.truth[k].C - 1));
  state.counters["max_rel_error"] = worst;
  state.counters["C03_rel_error"] = std::abs(r.parameters(3) / s.truth[3].C - 1);
  state.counters["paper_ratio"] = 52 * 3600.0 / r.wall_seconds;  // the paper's 52 h for this case
  state.SetLabel(state.range(0) == 0 ? "exact" : "fd_forward");
}
BENCHMARK(BM_Identify)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
