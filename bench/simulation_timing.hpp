// Times whole FE simulations in a Google Benchmark loop (fem_benchmark, linear_solver_benchmark).
// Counters: dofs, Newton iterations, factorizations, ms per run in factorizations, their share of the
// run's time, the inverse (wall over factorizations) and the last grip force.
#pragma once

#include <benchmark/benchmark.h>

#include "tricot/fem/solver.hpp"

namespace tricot::bench {

inline void time_simulation(benchmark::State& state, const fem::TestModel& t, const fem::Law& law,
                            const fem::SolveOptions& o) {
  fem::SimulationResult r;
  double seconds = 0, factorization = 0;
  for (auto _ : state) {
    r = fem::simulate(t, law, o);
    seconds += r.seconds;
    factorization += r.factorization_seconds;
  }
  if (!r.usable()) state.SkipWithError(r.message.c_str());
  int iterations = 0;
  for (const auto& s : r.steps) iterations += s.iterations;
  state.counters["dofs"] = t.mesh.dofs();
  state.counters["newton"] = iterations;
  state.counters["factorizations"] = r.factorizations;
  state.counters["fact_ms"] = 1e3 * factorization / static_cast<double>(state.iterations());
  state.counters["fact_share"] = factorization / seconds;
  state.counters["wall_over_fact"] = seconds / factorization;
  state.counters["force_N"] = r.steps.empty() ? 0 : r.steps.back().edge_force;
}

}  // namespace tricot::bench
