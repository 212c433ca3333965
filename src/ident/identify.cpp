// Levenberg–Marquardt on Ceres (docs/theory.md §3): one cost function holds the whole residual vector of
// eq. (1) over the LM variables x = J / scale; an iteration callback applies the paper's ε and δ
// criteria, records the history and writes checkpoints; the stability test restarts LM.
#include "tricot/ident/identify.hpp"

#include "lm.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/core/format.hpp"

namespace tricot::ident {

const char* to_string(Termination t) {
  switch (t) {
    case Termination::objective_below_epsilon: return "objective_below_epsilon";
    case Termination::step_below_delta: return "step_below_delta";
    case Termination::objective_stalled: return "objective_stalled";
    case Termination::gradient_below_tolerance: return "gradient_below_tolerance";
    case Termination::max_iterations: return "max_iterations";
    case Termination::unstable: return "unstable";
    case Termination::fe_failure: return "fe_failure";
  }
  return "?";
}

const char* to_string(Phase p) {
  switch (p) {
    case Phase::lm: return "lm";
    case Phase::stability: return "stability";
    case Phase::done: return "done";
  }
  return "?";
}

std::optional<Phase> phase_from_string(const std::string& s) {
  for (Phase p : {Phase::lm, Phase::stability, Phase::done})
    if (s == to_string(p)) return p;
  return std::nullopt;
}

bool IdentifyResult::converged() const {
  return termination == Termination::objective_below_epsilon || termination == Termination::step_below_delta ||
         termination == Termination::objective_stalled || termination == Termination::gradient_below_tolerance;
}

std::string IdentifyResult::brief_report() const {
  char f[32];
  std::snprintf(f, sizeof f, "%.4g", objective);
  return std::string(converged() ? "converged" : "NOT converged") + ": " + to_string(termination) + " after " +
         std::to_string(iterations) + " LM iterations, " + std::to_string(evaluations) + " evaluations, " +
         format_duration(wall_seconds) + " (" + message + "), f = " + f;
}

std::vector<double> IdentifyResult::std_error() const {
  const auto& s = uncertainty.std_error;
  return std::vector<double>(s.data(), s.data() + s.size());
}

namespace {

void check(bool ok, const char* field, double got, const std::string& expected) {
  if (!ok)
    throw InputError(Location{"", 0, std::string("identify.") + field}, "out of range", format_number(got), expected);
}

}  // namespace

void IdentifyOptions::validate() const {
  // First the keys whose range is open at an end, so that the message says so.
  check(delta > 0 && delta < 1, "delta", delta, "(0, 1)");
  check(function_tolerance >= 0 && function_tolerance < 1, "function_tolerance", function_tolerance, "[0, 1)");
  check(stability_eta > 0 && stability_eta < 1, "stability_eta", stability_eta, "(0, 1)");
  check(fd_step > 0 && fd_step <= 0.1, "fd_step", fd_step, "(0, 0.1]");
  check(initial_trust_region_radius > 0 && initial_trust_region_radius <= 1e16, "initial_trust_region_radius",
        initial_trust_region_radius, "(0, 1e16]");
  check(barrier_growth >= 0 && barrier_growth < 1, "barrier_growth", barrier_growth, "[0, 1)");
  check_ranges(*this);
  if (start && resume_from)
    throw InputError(Location{"", 0, "identify.start"}, "a start point and a checkpoint to resume from", "one of them",
                     "both");
}

using namespace detail;

namespace {

/// Maps a Ceres summary without a callback verdict onto the paper's terminations, from its
/// TerminationType and the tests Ceres's trust-region loop makes (never its message text). At
/// CONVERGENCE: the gradient and trust-region tests are made on the last recorded iteration; otherwise
/// Ceres stopped on the trial step `trial` from the accepted point `x`, which it does not record: the
/// step test (parameter_tolerance, here δ) comes first, then the function test.
Termination from_ceres(const ceres::Solver::Summary& s, const ceres::Solver::Options& so, const Eigen::VectorXd& x,
                       const Eigen::VectorXd& trial) {
  if (s.termination_type == ceres::NO_CONVERGENCE) return Termination::max_iterations;
  if (s.termination_type != ceres::CONVERGENCE || s.iterations.empty()) return Termination::fe_failure;
  const ceres::IterationSummary& last = s.iterations.back();
  if (last.step_is_successful && last.gradient_max_norm <= so.gradient_tolerance)
    return Termination::gradient_below_tolerance;
  if (last.trust_region_radius <= so.min_trust_region_radius) return Termination::step_below_delta;  // collapsed
  const double tolerance = so.parameter_tolerance * (x.norm() + so.parameter_tolerance);
  if (trial.size() == x.size() && (x - trial).norm() <= tolerance) return Termination::step_below_delta;
  return Termination::objective_stalled;  // |Δf| ≤ function_tolerance · f
}

/// The paper's stability test (docs/theory.md §3): f at J* with each coefficient scaled by (1 ± η). Returns
/// the best trial's LM variables when its f is below f*. A trial whose f the problem bounds from below
/// by f* or more without the FE (Problem::lower_bound: the stability barrier) cannot be below it, and
/// is not run (IdentifyResult::skipped_evaluations): the same verdict, without its FE.
std::optional<Eigen::VectorXd> stability_trial(const Problem& problem, const IdentifyOptions& options,
                                               const Eigen::VectorXd& scales, State& state) {
  const auto& params = problem.parameters();
  const Eigen::VectorXd J = scales.cwiseProduct(state.x);
  std::vector<Eigen::VectorXd> trials;
  for (Eigen::Index k = 0; k < J.size(); ++k)
    for (double sign : {1.0, -1.0}) {
      Eigen::VectorXd Jt = J;
      const double step = options.stability_eta * (J(k) != 0 ? std::abs(J(k)) : scales(k));
      Jt(k) = std::clamp(J(k) + sign * step, params[k].lower, params[k].upper);
      if (Jt(k) != J(k)) trials.push_back(Jt);
    }
  const int m = static_cast<int>(trials.size());
  // A decrease at the level of rounding is no evidence of a better minimum.
  const double to_beat = state.objective * (1 - 1e-10);
  std::vector<char> run(m);
  for (int i = 0; i < m; ++i) run[i] = problem.lower_bound(trials[i]) < to_beat;
  const int runs = static_cast<int>(std::count(run.begin(), run.end(), 1));
  std::vector<Evaluation> e(m);
  const int threads = thread_team(options.threads);
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (int i = 0; i < m; ++i)
    if (run[i]) e[i] = problem.evaluate(trials[i], false);
  state.evaluations += runs;
  state.skipped_evaluations += m - runs;
  int best = -1;
  for (int i = 0; i < m; ++i) {
    if (!run[i]) continue;
    if (!e[i].ok || !e[i].r.allFinite()) {
      ++state.failed_evaluations;
      continue;
    }
    if (best < 0 || e[i].objective() < e[best].objective()) best = i;
  }
  if (best < 0 || !(e[best].objective() < to_beat)) return std::nullopt;
  return trials[best].cwiseQuotient(scales);
}

/// One Ceres solve of LM from x (its box, active set and cut steps), through the Monitor: where it
/// stopped and why. A solve that the active set ended (held_changed) goes on in another from out.x.
struct LmSolve {
  Eigen::VectorXd x;
  bool held_changed = false;
  Termination termination = Termination::fe_failure;
  std::string message;
  std::string ceres_message;  ///< Ceres's own summary line
  bool ran = false;           ///< Ceres made an iteration
};

LmSolve lm_solve(const Problem& problem, const IdentifyOptions& options, const Reporter& reporter,
                 const std::vector<std::string>& names, const Eigen::VectorXd& scales, const Box& box, LmCost& cost,
                 State& state, bool record_start, std::chrono::steady_clock::time_point t0, Eigen::VectorXd x) {
  const auto& params = problem.parameters();
  const int n = static_cast<int>(params.size());
  LmSolve out;
  const bool cut_steps = options.barrier_growth > 0 && problem.has_lower_bound();
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem lm(po);
  lm.AddResidualBlock(&cost, nullptr, x.data());
  for (int k = 0; k < n; ++k) {
    if (std::isfinite(box.lo(k))) lm.SetParameterLowerBound(x.data(), k, box.lo(k));
    if (std::isfinite(box.hi(k))) lm.SetParameterUpperBound(x.data(), k, box.hi(k));
  }
  StepManifold::Fraction fraction;
  if (cut_steps)  // the barrier may grow by barrier_growth · f at the accepted point (Monitor keeps it)
    fraction = [&](const Eigen::VectorXd& x0, const Eigen::VectorXd& d) {
      return step_fraction(problem, scales, x0, d, options.barrier_growth * state.objective);
    };
  if (!state.held.empty() || fraction) lm.SetManifold(x.data(), new StepManifold(n, state.held, std::move(fraction)));
  Monitor monitor(options, reporter, names, scales, x, state, record_start, t0, cost, box);
  bool bounded = false;
  for (const auto& p : params) bounded = bounded || std::isfinite(p.lower) || std::isfinite(p.upper);
  const bool continues_a_solve = !record_start && !bounded;
  if (continues_a_solve) monitor.continue_step_test(options.delta);
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.jacobi_scaling = false;  // x is already relative; and the state then fits in a checkpoint
  so.max_num_iterations = std::max(0, options.max_iterations - state.iterations);
  so.function_tolerance = options.function_tolerance;
  so.gradient_tolerance = options.gradient_tolerance;
  so.parameter_tolerance = options.delta;
  so.initial_trust_region_radius = state.trust_region_radius;
  so.max_num_line_search_step_size_iterations = options.bounds_line_search ? options.line_search_trials : 0;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  so.update_state_every_iteration = true;
  so.num_threads = 1;
  so.callbacks.push_back(&monitor);
  // Where the problem keeps its simulations, the bounded line search interpolates f alone: its
  // trials need no Jacobian (cubic interpolation asks for the gradient at each one).
  if (problem.keeps_simulations()) so.line_search_interpolation_type = ceres::QUADRATIC;
  ceres::Solver::Summary summary;
  const int base = state.iterations;
  ceres::Solve(so, &lm, &summary);

  if (!summary.iterations.empty() && !monitor.stopped_by_step_test)
    state.iterations = base + summary.iterations.back().iteration;
  if (monitor.stopped_by_step_test) x = state.x;  // Ceres may have moved on to the trial
  if (monitor.held_changed) {                     // LM goes on from the accepted point with the new active set
    out.x = state.x;
    out.held_changed = true;
    return out;
  }
  Termination termination;
  std::string message;
  if (monitor.reason) {
    termination = *monitor.reason;
    message = monitor.message;
  } else {
    termination = from_ceres(summary, so, x, cost.last_trial);
    message = summary.message;
    // Ceres stopped (e.g. on its function tolerance) on a trial before any accepted step of a
    // resumed solve: the killed run made the step test first (Monitor::continue_step_test).
    if (continues_a_solve && termination == Termination::step_below_delta && summary.num_successful_steps <= 1 &&
        cost.last_trial.size() == x.size())
      message = step_test_message((x - cost.last_trial).norm(), x.norm(), options.delta);
    // The trust region collapsed because the model failed at every step LM tried from the last
    // accepted point: that point is not a minimum, LM was walled in (e.g. a force the trial
    // law cannot carry). Not a convergence.
    if (termination == Termination::step_below_delta && state.failed_since_accepted > 0) {
      termination = Termination::fe_failure;
      message = "LM was stopped by model failures: the last " + std::to_string(state.failed_since_accepted) +
                " trial steps failed (" + cost.last_failure + ")";
    }
    if (termination == Termination::fe_failure && !cost.last_failure.empty()) message = cost.last_failure;
  }
  out.x = x;
  out.termination = termination;
  out.message = message;
  out.ceres_message = summary.message;
  out.ran = !summary.iterations.empty();
  return out;
}

/// The run's answer from its final state: J*, f and its uncertainty from the Jacobian there (none
/// after an FE failure), and the run's counts.
IdentifyResult result_of(const Problem& problem, const IdentifyOptions& options, const std::vector<std::string>& names,
                         const Eigen::VectorXd& scales, const LmCost& cost, State& state,
                         std::chrono::steady_clock::time_point t0) {
  IdentifyResult result;
  result.names = names;
  result.jacobian = options.jacobian;
  result.termination = state.termination;
  result.message = state.message;
  result.stability_passed = state.stability_passed;
  result.parameters = scales.cwiseProduct(state.x);
  // J at the start of the whole run (a resumed run's history begins there too).
  result.start = state.history.empty() ? result.parameters : state.history.front().parameters;
  result.objective = state.objective;
  if (result.termination != Termination::fe_failure) {
    if (const Evaluation* e = cost.at(state.x, true)) {
      result.objective = e->objective();
      result.uncertainty = uncertainty(e->jacobian, e->r, result.parameters, scales, problem.residual_variance());
      result.residuals = e->r;
    }
  }
  result.iterations = state.iterations;
  result.evaluations = state.evaluations;
  result.jacobian_evaluations = state.jacobian_evaluations;
  result.failed_evaluations = state.failed_evaluations;
  result.skipped_evaluations = state.skipped_evaluations;
  result.restarts = state.restarts;
  result.history = std::move(state.history);
  result.wall_seconds =
      state.wall_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace

IdentifyResult identify(const Problem& problem, const IdentifyOptions& options, const Reporter& reporter) {
  options.validate();
  const auto& params = problem.parameters();
  validate(params);
  if (options.jacobian == JacobianMode::exact && !problem.has_exact_jacobian())
    throw InputError(Location{"", 0, "identify.jacobian"}, "this problem has no exact Jacobian", "exact",
                     "finite_difference");
  const auto t0 = std::chrono::steady_clock::now();
  const int n = static_cast<int>(params.size());
  std::vector<std::string> names;
  Eigen::VectorXd scales(n);
  for (int k = 0; k < n; ++k) {
    names.push_back(params[k].name);
    scales(k) = params[k].resolved_scale();
  }

  State state;
  state.trust_region_radius = options.initial_trust_region_radius;
  bool resumed = false;
  if (options.resume_from) {
    const Checkpoint& c = *options.resume_from;
    if (c.names != names || c.scales.size() != n || c.scales != scales || c.x.size() != n)
      throw InputError(Location{"", 0, "resume"}, "the checkpoint belongs to another identification",
                       "parameters and scales of the checkpoint", "those of the project");
    static_cast<LmProgress&>(state) = c;
    resumed = true;
  } else if (options.start) {
    if (options.start->size() != n)
      throw InputError(Location{"", 0, "identify.start"}, "one start value per parameter",
                       std::to_string(n) + " values", std::to_string(options.start->size()));
    state.x = options.start->cwiseQuotient(scales);
  } else {
    state.x.resize(n);
    for (int k = 0; k < n; ++k) state.x(k) = params[k].start / scales(k);
  }
  const auto checkpoint = [&] { save_checkpoint(options, names, scales, state, t0); };
  // Ends the run: `termination` and `message` are the run's; the checkpoint says it is over.
  const auto finish = [&](Termination t, std::string message) {
    state.termination = t;
    state.message = std::move(message);
    state.phase = Phase::done;
    checkpoint();
  };

  LmCost cost(problem, options.jacobian_options(), scales, state);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Box box{Eigen::VectorXd::Constant(n, -kInf), Eigen::VectorXd::Constant(n, kInf)};
  for (int k = 0; k < n; ++k) {
    if (std::isfinite(params[k].lower)) box.lo(k) = params[k].lower / scales(k);
    if (std::isfinite(params[k].upper)) box.hi(k) = params[k].upper / scales(k);
  }
  // A start where the model fails ends here (Ceres would log its own failure otherwise). A finished
  // run (phase done) needs no evaluation before its final one.
  if (state.phase != Phase::done && !cost.at(state.x, options.jacobian == JacobianMode::exact))
    finish(Termination::fe_failure, "at the start point: " + cost.last_failure);

  if (!options.active_set) state.held.clear();  // a checkpoint of a run with the active set, resumed without
  // A run resumed in phase lm goes on from its checkpoint's point, whose history entry and
  // checkpoint exist; every later LM run (a stability restart) records its start.
  bool record_start = !(resumed && state.phase == Phase::lm);
  while (state.phase != Phase::done) {
    if (state.phase == Phase::lm) {
      Eigen::VectorXd x = state.x;  // Ceres' parameter block
      // A held variable that a stability restart moved off its bound is free again.
      std::erase_if(state.held, [&](int k) { return !box.at_lower(x, k) && !box.at_upper(x, k); });
      if (static_cast<int>(state.held.size()) == n) {  // nothing left to step in: a KKT test only
        if (!release_held(box, x, cost.gradient(x), options.gradient_tolerance, names, reporter, state.held)) {
          state.termination = Termination::gradient_below_tolerance;
          state.message = "every coefficient is held at a bound, where f decreases only out of the box";
          state.phase = options.stability_test ? Phase::stability : Phase::done;
          if (state.phase == Phase::done) {
            finish(state.termination, state.message);
            break;
          }
          checkpoint();
          continue;
        }
      }
      const LmSolve solve = lm_solve(problem, options, reporter, names, scales, box, cost, state, record_start, t0, x);
      record_start = true;
      if (solve.held_changed) {  // LM goes on from the accepted point with the new active set
        record_start = false;
        continue;
      }
      const Termination termination = solve.termination;
      const std::string& message = solve.message;
      x = solve.x;
      if (termination == Termination::fe_failure || !solve.ran) {
        finish(Termination::fe_failure, message.empty() ? solve.ceres_message : message);
        break;
      }
      // The best point Ceres found: the last accepted one, whose objective the monitor recorded (a
      // resumed run reads the same values from the checkpoint).
      state.x = x;
      state.termination = termination;
      state.message = message;
      const bool converged = termination != Termination::max_iterations;
      // Converged in the free variables: the KKT test of the held ones.
      if (converged && termination != Termination::objective_below_epsilon && !state.held.empty() &&
          release_held(box, x, cost.gradient(x), options.gradient_tolerance, names, reporter, state.held)) {
        checkpoint();
        record_start = false;
        continue;
      }
      if (!converged || !options.stability_test) {
        finish(termination, message);
        break;
      }
      state.phase = Phase::stability;
      checkpoint();
    }
    // Phase stability: the paper's test at LM's answer, then a restart or the end.
    const auto better = stability_trial(problem, options, scales, state);
    if (!better) {
      state.stability_passed = true;
      finish(state.termination, state.message);
      break;
    }
    if (state.restarts >= options.max_restarts) {
      finish(Termination::unstable,
             "the stability test still lowers f after " + std::to_string(state.restarts) + " restarts");
      break;
    }
    if (state.iterations >= options.max_iterations) {
      ++state.restarts;
      state.x = *better;
      finish(Termination::max_iterations, "max_iterations reached during the stability restarts");
      break;
    }
    // The restart's first LM iteration writes its checkpoint (phase lm); a run killed before that
    // repeats this test, which gives the same point.
    ++state.restarts;
    state.x = *better;
    state.trust_region_radius = options.initial_trust_region_radius;
    state.phase = Phase::lm;
  }

  return result_of(problem, options, names, scales, cost, state, t0);
}

}  // namespace tricot::ident
