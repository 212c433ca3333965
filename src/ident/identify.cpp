// Levenberg–Marquardt on Ceres (THEORY §3): one cost function holds the whole residual vector of
// eq. (1) over the LM variables x = J / scale; an iteration callback applies the paper's ε and δ
// criteria, records the history and writes checkpoints; the stability test restarts LM.
#include "tricot/ident/identify.hpp"

#include <ceres/ceres.h>
#include <omp.h>

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
  if (!ok) throw InputError(Location{"", 0, std::string("identify.") + field}, "out of range", format_number(got), expected);
}

}  // namespace

void IdentifyOptions::validate() const {
  check(epsilon >= 0 && std::isfinite(epsilon), "epsilon", epsilon, ">= 0");
  check(delta > 0 && delta < 1, "delta", delta, "(0, 1)");
  check(function_tolerance >= 0 && function_tolerance < 1, "function_tolerance", function_tolerance, "[0, 1)");
  check(gradient_tolerance >= 0 && std::isfinite(gradient_tolerance), "gradient_tolerance", gradient_tolerance, ">= 0");
  check(max_iterations >= 1 && max_iterations <= 100000, "max_iterations", max_iterations, "1 to 100000");
  check(stability_eta > 0 && stability_eta < 1, "stability_eta", stability_eta, "(0, 1)");
  check(max_restarts >= 0 && max_restarts <= 1000, "max_restarts", max_restarts, "0 to 1000");
  check(initial_trust_region_radius > 0 && initial_trust_region_radius <= 1e16, "initial_trust_region_radius",
        initial_trust_region_radius, "(0, 1e16]");
  jacobian_options().validate();
}

namespace {

/// Run state, carried across LM restarts and through checkpoints.
// LmProgress at the current point (wall_seconds: spent by the run this one resumes), and the trial
// points where the model failed since the last accepted step.
struct State : LmProgress {
  int failed_since_accepted = 0;
};

/// The whole residual vector as one Ceres cost function of x = J / scale. It keeps the last
/// evaluation: Ceres evaluates a trial without the Jacobian, then the accepted point again with it;
/// in exact mode the trial already carries the sensitivities, so no FE run is repeated.
class LmCost final : public ceres::CostFunction {
 public:
  LmCost(const Problem& problem, const JacobianOptions& options, const Eigen::VectorXd& scales, State& state)
      : problem_(problem), options_(options), scales_(scales), state_(state) {
    set_num_residuals(problem.residuals());
    mutable_parameter_block_sizes()->push_back(static_cast<int>(scales.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Index n = scales_.size();
    const Eigen::Map<const Eigen::VectorXd> x(parameters[0], n);
    const bool want_jacobian = jacobians && jacobians[0];
    if (!want_jacobian) last_trial = x;  // Ceres evaluates each trial point without the Jacobian
    const Evaluation* e = at(x, want_jacobian);
    if (!e) return false;
    Eigen::Map<Eigen::VectorXd>(residuals, e->r.size()) = e->r;
    if (want_jacobian) {
      ++state_.jacobian_evaluations;
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          jacobians[0], e->r.size(), n) = e->jacobian * scales_.asDiagonal();  // ∂r/∂x = ∂r/∂J · scale
    }
    return true;
  }

  /// The evaluation at x (from the cache when possible), or nullptr when the model fails there.
  const Evaluation* at(const Eigen::VectorXd& x, bool jacobian) const {
    const bool hit = valid_ && cache_x_ == x;
    if (hit && (!jacobian || cache_.jacobian.size() > 0)) return remember(&cache_, jacobian);
    // The last point Ceres took a Jacobian at (the accepted one): the final covariance needs it
    // after later trials have replaced the cache.
    if (accepted_valid_ && accepted_x_ == x) return &accepted_;
    // Exact mode: ask for sensitivities with every trial, the accepted one then needs no second run.
    const bool with_jacobian = jacobian || options_.mode == JacobianMode::exact;
    Evaluation e = evaluate(problem_, scales_.cwiseProduct(x), with_jacobian, options_, hit ? &cache_ : nullptr);
    state_.evaluations += e.evaluations;
    if (e.ok && !e.r.allFinite()) {
      e.ok = false;
      e.message = "non-finite residual";
    }
    if (e.ok && with_jacobian && !e.jacobian.allFinite()) {
      e.ok = false;
      e.message = "non-finite Jacobian";
    }
    if (!e.ok) {
      ++state_.failed_evaluations;
      ++state_.failed_since_accepted;
      last_failure = e.message;
      valid_ = false;
      return nullptr;
    }
    cache_x_ = x;
    cache_ = std::move(e);
    valid_ = true;
    return remember(&cache_, jacobian);
  }

  mutable std::string last_failure;
  /// The last point evaluated without the Jacobian: Ceres's last trial step.
  mutable Eigen::VectorXd last_trial;

 private:
  const Problem& problem_;
  JacobianOptions options_;
  Eigen::VectorXd scales_;
  State& state_;
  const Evaluation* remember(const Evaluation* e, bool jacobian) const {
    if (jacobian) {
      accepted_x_ = cache_x_;
      accepted_ = *e;
      accepted_valid_ = true;
    }
    return e;
  }

  mutable bool valid_ = false, accepted_valid_ = false;
  mutable Eigen::VectorXd cache_x_, accepted_x_;
  mutable Evaluation cache_, accepted_;
};

/// After every LM iteration: history, checkpoint, progress, and the paper's ε (eq. 2) and δ (eq. 3).
class Monitor final : public ceres::IterationCallback {
 public:
  Monitor(const IdentifyOptions& options, const Reporter& reporter, const std::vector<std::string>& names,
          const Eigen::VectorXd& scales, const Eigen::VectorXd& x_block, State& state, bool record_start,
          std::chrono::steady_clock::time_point t0)
      : options_(options), reporter_(reporter), names_(names), scales_(scales), x_(x_block), state_(state),
        record_start_(record_start), base_iterations_(state.iterations), t0_(t0) {}

  std::optional<Termination> reason;
  std::string message;

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    const int iteration = base_iterations_ + s.iteration;
    if (s.iteration == 0 || s.step_is_successful) {
      state_.failed_since_accepted = 0;
      state_.x = x_;
      state_.objective = s.cost;
      state_.trust_region_radius = s.trust_region_radius;
      state_.iterations = iteration;
      if (s.iteration > 0 || record_start_) {
        state_.history.push_back({iteration, s.cost, scales_.cwiseProduct(x_), state_.restarts});
        checkpoint();
      }
    }
    report(iteration, s);
    if (!(s.iteration == 0 || s.step_is_successful)) return ceres::SOLVER_CONTINUE;
    if (s.cost < options_.epsilon) {
      reason = Termination::objective_below_epsilon;
      message = "f = " + format_number(s.cost) + " < epsilon = " + format_number(options_.epsilon) + " (eq. 2)";
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    if (s.iteration > 0) {
      // Eq. (3): the paper's t_i = ΔJ / J_i, element-wise.
      double t = 0;
      for (Eigen::Index k = 0; k < x_.size(); ++k) {
        const double dx = std::abs(x_(k) - x_prev_(k));
        t = std::max(t, x_prev_(k) != 0 ? dx / std::abs(x_prev_(k)) : dx);
      }
      if (t < options_.delta) {
        reason = Termination::step_below_delta;
        message = "relative step max|t| = " + format_number(t) + " < delta = " + format_number(options_.delta) + " (eq. 3)";
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
    }
    x_prev_ = x_;
    return ceres::SOLVER_CONTINUE;
  }

 private:
  void checkpoint() const {
    if (!options_.on_checkpoint) return;
    Checkpoint c;
    static_cast<LmProgress&>(c) = state_;
    c.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    c.names = names_;
    c.scales = scales_;
    c.parameters = scales_.cwiseProduct(state_.x);
    options_.on_checkpoint(c);
  }

  void report(int iteration, const ceres::IterationSummary& s) const {
    std::string detail = "f = " + format_number(state_.objective);
    if (s.iteration > 0 && !s.step_is_successful) detail += " (step rejected)";
    for (size_t k = 0; k < names_.size(); ++k) detail += ", " + names_[k] + " = " + format_number(scales_(k) * state_.x(k));
    reporter_.report({"identify", static_cast<size_t>(iteration), static_cast<size_t>(options_.max_iterations), detail});
  }

  const IdentifyOptions& options_;
  const Reporter& reporter_;
  const std::vector<std::string>& names_;
  const Eigen::VectorXd& scales_;
  const Eigen::VectorXd& x_;
  State& state_;
  bool record_start_;
  int base_iterations_;
  std::chrono::steady_clock::time_point t0_;
  Eigen::VectorXd x_prev_ = x_;
};

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

/// The paper's stability test (THEORY §3): f at J* with each coefficient scaled by (1 ± η). Returns
/// the best trial's LM variables when its f is below f*.
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
  std::vector<Evaluation> e(m);
  // More threads than cores never speeds this up, and a team of 1024 can fail to start (libgomp aborts).
  const int threads = options.threads > 0 ? std::min(options.threads, omp_get_num_procs()) : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (int i = 0; i < m; ++i) e[i] = problem.evaluate(trials[i], false);
  state.evaluations += m;
  int best = -1;
  for (int i = 0; i < m; ++i) {
    if (!e[i].ok || !e[i].r.allFinite()) {
      ++state.failed_evaluations;
      continue;
    }
    if (best < 0 || e[i].objective() < e[best].objective()) best = i;
  }
  // A decrease at the level of rounding is no evidence of a better minimum.
  if (best < 0 || !(e[best].objective() < state.objective * (1 - 1e-10))) return std::nullopt;
  return trials[best].cwiseQuotient(scales);
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
  } else {
    state.x.resize(n);
    for (int k = 0; k < n; ++k) state.x(k) = params[k].start / scales(k);
  }

  IdentifyResult result;
  result.names = names;
  result.jacobian = options.jacobian;
  result.start = scales.cwiseProduct(state.x);
  LmCost cost(problem, options.jacobian_options(), scales, state);
  // A start where the model fails ends here (Ceres would log its own failure otherwise).
  const bool start_ok = cost.at(state.x, options.jacobian == JacobianMode::exact) != nullptr;
  if (!start_ok) result.message = "at the start point: " + cost.last_failure;

  for (bool first = true; start_ok; first = false) {
    Eigen::VectorXd x = state.x;  // Ceres' parameter block
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem lm(po);
    lm.AddResidualBlock(&cost, nullptr, x.data());
    for (int k = 0; k < n; ++k) {
      if (std::isfinite(params[k].lower)) lm.SetParameterLowerBound(x.data(), k, params[k].lower / scales(k));
      if (std::isfinite(params[k].upper)) lm.SetParameterUpperBound(x.data(), k, params[k].upper / scales(k));
    }
    Monitor monitor(options, reporter, names, scales, x, state, !(first && resumed), t0);
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
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    so.update_state_every_iteration = true;
    so.num_threads = 1;
    so.callbacks.push_back(&monitor);
    ceres::Solver::Summary summary;
    const int base = state.iterations;
    ceres::Solve(so, &lm, &summary);

    if (!summary.iterations.empty()) state.iterations = base + summary.iterations.back().iteration;
    if (monitor.reason) {
      result.termination = *monitor.reason;
      result.message = monitor.message;
    } else {
      result.termination = from_ceres(summary, so, x, cost.last_trial);
      result.message = summary.message;
      // The trust region collapsed because the model failed at every step LM tried from the last
      // accepted point: that point is not a minimum, LM was walled in (e.g. a force the trial
      // law cannot carry). Not a convergence.
      if (result.termination == Termination::step_below_delta && state.failed_since_accepted > 0) {
        result.termination = Termination::fe_failure;
        result.message = "LM was stopped by model failures: the last " +
                         std::to_string(state.failed_since_accepted) + " trial steps failed (" + cost.last_failure +
                         ")";
      }
      if (result.termination == Termination::fe_failure && !cost.last_failure.empty())
        result.message = cost.last_failure;
    }
    if (result.termination == Termination::fe_failure || summary.iterations.empty()) {
      if (result.message.empty()) result.message = summary.message;
      if (summary.iterations.empty()) result.termination = Termination::fe_failure;
      break;
    }
    state.x = x;  // the best point Ceres found
    state.objective = summary.final_cost;
    if (!result.converged() || !options.stability_test) break;
    const auto better = stability_trial(problem, options, scales, state);
    if (!better) {
      result.stability_passed = true;
      break;
    }
    if (state.restarts >= options.max_restarts) {
      result.termination = Termination::unstable;
      result.message = "the stability test still lowers f after " + std::to_string(state.restarts) + " restarts";
      break;
    }
    ++state.restarts;
    state.x = *better;
    state.trust_region_radius = options.initial_trust_region_radius;
    if (state.iterations >= options.max_iterations) {
      result.termination = Termination::max_iterations;
      result.message = "max_iterations reached during the stability restarts";
      break;
    }
  }

  result.parameters = scales.cwiseProduct(state.x);
  result.objective = state.objective;
  if (result.termination != Termination::fe_failure) {
    if (const Evaluation* e = cost.at(state.x, true)) {
      result.objective = e->objective();
      result.uncertainty = uncertainty(e->jacobian, e->r, result.parameters, scales, problem.residual_variance());
    }
  }
  result.iterations = state.iterations;
  result.evaluations = state.evaluations;
  result.jacobian_evaluations = state.jacobian_evaluations;
  result.failed_evaluations = state.failed_evaluations;
  result.restarts = state.restarts;
  result.history = std::move(state.history);
  result.wall_seconds = state.wall_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace tricot::ident
