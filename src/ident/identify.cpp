// Levenberg–Marquardt on Ceres (docs/theory.md §3): one cost function holds the whole residual vector of
// eq. (1) over the LM variables x = J / scale; an iteration callback applies the paper's ε and δ
// criteria, records the history and writes checkpoints; the stability test restarts LM.
#include "tricot/ident/identify.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <functional>
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
  check(line_search_trials >= 1 && line_search_trials <= 100, "line_search_trials", line_search_trials, "1 to 100");
  check(initial_trust_region_radius > 0 && initial_trust_region_radius <= 1e16, "initial_trust_region_radius",
        initial_trust_region_radius, "(0, 1e16]");
  check(barrier_growth >= 0 && barrier_growth < 1, "barrier_growth", barrier_growth, "[0, 1)");
  if (start && resume_from)
    throw InputError(Location{"", 0, "identify.start"}, "a start point and a checkpoint to resume from",
                     "one of them", "both");
  jacobian_options().validate();
}

namespace {

/// Run state, carried across LM restarts and through checkpoints.
// LmProgress at the current point (wall_seconds: spent by the run this one resumes), and the trial
// points where the model failed since the last accepted step.
struct State : LmProgress {
  int failed_since_accepted = 0;
};

/// The whole residual vector as one Ceres cost function of x = J / scale. It keeps the last few
/// evaluations: Ceres evaluates a trial without the Jacobian, then the accepted point again with it;
/// in exact mode the trial carries the sensitivities, or the problem keeps its simulations and adds
/// them there (Problem::keeps_simulations), so no FE run is repeated.
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

  /// The evaluation at x (from the recent ones when possible), or nullptr when the model fails there.
  const Evaluation* at(const Eigen::VectorXd& x, bool jacobian) const {
    auto found = std::find_if(recent_.begin(), recent_.end(), [&](const Recent& c) { return c.x == x; });
    if (found != recent_.end() && (!jacobian || found->e.jacobian.size() > 0)) return &found->e;
    // Exact mode: the sensitivities come with every trial, so the accepted one needs no second run,
    // unless the problem keeps its simulations (then they are added where LM asks for them).
    const bool with_jacobian = jacobian || (options_.mode == JacobianMode::exact && !problem_.keeps_simulations());
    Evaluation e = evaluate(problem_, scales_.cwiseProduct(x), with_jacobian, options_,
                            found != recent_.end() ? &found->e : nullptr);
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
      return nullptr;
    }
    if (found != recent_.end()) recent_.erase(found);
    recent_.push_front({x, std::move(e)});
    if (recent_.size() > kRecent) recent_.pop_back();
    return &recent_.front().e;
  }

  /// ∂f/∂x at x (f = ½ r·r, LM units) from the evaluation with the Jacobian there (cached at an
  /// accepted point); empty when the model fails at x.
  Eigen::VectorXd gradient(const Eigen::VectorXd& x) const {
    const Evaluation* e = at(x, true);
    if (!e) return {};
    return scales_.cwiseProduct(e->jacobian.transpose() * e->r);
  }

  mutable std::string last_failure;
  /// The last point evaluated without the Jacobian: Ceres's last trial step.
  mutable Eigen::VectorXd last_trial;

 private:
  const Problem& problem_;
  JacobianOptions options_;
  Eigen::VectorXd scales_;
  State& state_;
  /// The points evaluated last, newest first: Ceres asks again for the accepted point (its Jacobian)
  /// after trials, for the line search's first trial as the step's candidate, and identify() for the
  /// answer's covariance.
  struct Recent {
    Eigen::VectorXd x;
    Evaluation e;
  };
  static constexpr std::size_t kRecent = 8;
  mutable std::deque<Recent> recent_;
};

/// LM's steps in x: the variables held at a bound stay (the active set), and with a `fraction` the
/// step is cut along its direction (IdentifyOptions::barrier_growth). Ceres moves by Plus for each
/// trust-region step and each trial of its line search; its bounds are applied after.
class StepManifold final : public ceres::Manifold {
 public:
  /// fraction(x, d): the share t ∈ [0, 1] of the step d from x to take; empty = 1.
  using Fraction = std::function<double(const Eigen::VectorXd&, const Eigen::VectorXd&)>;
  StepManifold(int n, const std::vector<int>& held, Fraction fraction) : n_(n), fraction_(std::move(fraction)) {
    for (int k = 0; k < n; ++k)
      if (!std::binary_search(held.begin(), held.end(), k)) free_.push_back(k);
  }
  int AmbientSize() const override { return n_; }
  int TangentSize() const override { return static_cast<int>(free_.size()); }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n_);
    for (size_t i = 0; i < free_.size(); ++i) d(free_[i]) = delta[i];
    const Eigen::Map<const Eigen::VectorXd> x0(x, n_);
    const double t = fraction_ && d.squaredNorm() > 0 ? fraction_(x0, d) : 1.0;
    Eigen::Map<Eigen::VectorXd>(x_plus_delta, n_) = x0 + t * d;
    return true;
  }
  /// At δ = 0 the step is whole (the fraction is 1 for short enough steps): the free variables' selection.
  bool PlusJacobian(const double*, double* jacobian) const override {
    const int m = TangentSize();
    std::fill(jacobian, jacobian + n_ * m, 0.0);
    for (int i = 0; i < m; ++i) jacobian[free_[i] * m + i] = 1;
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    for (size_t i = 0; i < free_.size(); ++i) y_minus_x[i] = y[free_[i]] - x[free_[i]];
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    const int m = TangentSize();
    std::fill(jacobian, jacobian + n_ * m, 0.0);
    for (int i = 0; i < m; ++i) jacobian[i * n_ + free_[i]] = 1;
    return true;
  }

 private:
  int n_;
  std::vector<int> free_;
  Fraction fraction_;
};

/// The largest share t ∈ [0, 1] of the step d from x (LM units) along which the problem's FE-free
/// part of f (Problem::lower_bound) grows by at most `allowance`: 1 when the whole step keeps within
/// it, else found by bisection (to 2⁻⁴⁰ of the step).
double step_fraction(const Problem& problem, const Eigen::VectorXd& scales, const Eigen::VectorXd& x,
                     const Eigen::VectorXd& d, double allowance) {
  const double limit = problem.lower_bound(scales.cwiseProduct(x)) + allowance;
  const auto within = [&](double t) { return problem.lower_bound(scales.cwiseProduct(x + t * d)) <= limit; };
  if (within(1)) return 1;
  double lo = 0, hi = 1;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (within(mid) ? lo : hi) = mid;
  }
  return lo;
}

/// The box of the LM variables (the parameters' bounds / scale; ±∞ where none), as Ceres gets it.
struct Box {
  Eigen::VectorXd lo, hi;
  bool at_lower(const Eigen::VectorXd& x, Eigen::Index k) const { return x(k) <= lo(k); }
  bool at_upper(const Eigen::VectorXd& x, Eigen::Index k) const { return x(k) >= hi(k); }
  /// f decreases out of the box at x along variable k, which sits on its bound.
  bool pushed_out(const Eigen::VectorXd& x, const Eigen::VectorXd& g, Eigen::Index k) const {
    return (at_lower(x, k) && g(k) > 0) || (at_upper(x, k) && g(k) < 0);
  }
};

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// The active set's release: the held variables whose gradient at x points into the box (beyond
/// `tolerance`) are freed and named in the log. At a point where LM stopped, this is the KKT test of a
/// bound-constrained minimum. Returns whether any was freed (none where the model fails at x).
bool release_held(const Box& box, const Eigen::VectorXd& x, const Eigen::VectorXd& g, double tolerance,
                  const std::vector<std::string>& names, const Reporter& reporter, std::vector<int>& held) {
  if (g.size() != x.size()) return false;
  std::vector<std::string> released;
  std::vector<int> keep;
  for (int k : held) {
    const bool inward = box.at_lower(x, k) ? g(k) < -tolerance : g(k) > tolerance;
    if (inward) released.push_back(names[k]);
    else keep.push_back(k);
  }
  held = std::move(keep);
  if (!released.empty()) reporter.info("identify: released from its bound (f decreases into the box): " + joined(released));
  return !released.empty();
}

/// Ceres's message for its parameter tolerance, for the test a resumed run makes itself (Monitor).
std::string step_test_message(double step_norm, double x_norm, double delta) {
  char m[128];
  std::snprintf(m, sizeof m, "Parameter tolerance reached. Relative step_norm: %e <= %e.", step_norm / (x_norm + delta),
                delta);
  return m;
}

/// Hands the state to on_checkpoint (wall time: the resumed runs' and this one's).
void save_checkpoint(const IdentifyOptions& options, const std::vector<std::string>& names,
                     const Eigen::VectorXd& scales, const State& state, std::chrono::steady_clock::time_point t0) {
  if (!options.on_checkpoint) return;
  Checkpoint c;
  static_cast<LmProgress&>(c) = state;
  c.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  c.names = names;
  c.scales = scales;
  c.parameters = scales.cwiseProduct(state.x);
  options.on_checkpoint(c);
}

/// After every LM iteration: the paper's ε (eq. 2) and δ (eq. 3), history, checkpoint, progress.
class Monitor final : public ceres::IterationCallback {
 public:
  Monitor(const IdentifyOptions& options, const Reporter& reporter, const std::vector<std::string>& names,
          const Eigen::VectorXd& scales, const Eigen::VectorXd& x_block, State& state, bool record_start,
          std::chrono::steady_clock::time_point t0, const LmCost& cost, const Box& box)
      : options_(options), reporter_(reporter), names_(names), scales_(scales), x_(x_block), state_(state),
        record_start_(record_start), base_iterations_(state.iterations), t0_(t0), cost_(cost), box_(box) {}

  std::optional<Termination> reason;
  std::string message;
  /// The active set changed at the last accepted point: this solve ends there, LM goes on in another.
  bool held_changed = false;

  /// A resumed run continues LM inside a fresh Ceres solve, and Ceres makes its step test (parameter
  /// tolerance, ‖Δx‖ ≤ δ(‖x‖ + δ)) only after a first accepted step of a solve (before it, its ‖x‖ is
  /// unset) unless the problem has bounds. The run that was killed made it on every trial step, so
  /// the resumed one makes it here until its first accepted step: it stops where the killed run would
  /// have, at the same iteration.
  void continue_step_test(double delta) {
    step_test_norm_ = x_.norm();
    step_test_delta_ = delta;
  }
  bool stopped_by_step_test = false;

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    const int iteration = base_iterations_ + s.iteration;
    if (step_test_norm_ >= 0 && s.iteration > 0 && s.step_norm > 0 &&
        s.step_norm <= step_test_delta_ * (step_test_norm_ + step_test_delta_)) {
      // As Ceres would have stopped before this trial: the state stays at the last accepted point.
      reason = Termination::step_below_delta;
      message = step_test_message(s.step_norm, step_test_norm_, step_test_delta_);
      stopped_by_step_test = true;
      state_.iterations = iteration - 1;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    const bool accepted = s.iteration == 0 || s.step_is_successful;
    if (s.iteration > 0 && s.step_is_successful) step_test_norm_ = -1;  // Ceres's own test from here on
    if (accepted) {
      state_.failed_since_accepted = 0;
      state_.x = x_;
      state_.objective = s.cost;
      state_.trust_region_radius = s.trust_region_radius;
      state_.iterations = iteration;
      verdict(s);
      if (s.iteration > 0) update_active_set(true);
      if (reason) {  // LM stops here: the checkpoint says so, a resumed run must not go on
        state_.phase = options_.stability_test ? Phase::stability : Phase::done;
        state_.termination = *reason;
        state_.message = message;
      }
      bool saved = false;
      if (s.iteration > 0 || record_start_) {
        state_.history.push_back({iteration, s.cost, scales_.cwiseProduct(x_), state_.restarts});
        checkpoint();
        saved = true;
      }
      if (held_changed && !saved) checkpoint();
    } else {
      update_active_set(false);
      if (held_changed) {  // the accepted point, with the new set; the rejected trial counts
        state_.iterations = iteration;
        checkpoint();
      }
    }
    report(iteration, s);
    if (held_changed) return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    if (!accepted) return ceres::SOLVER_CONTINUE;
    if (reason) return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    x_prev_ = x_;
    return ceres::SOLVER_CONTINUE;
  }

  /// Writes the state (progress and phase) through on_checkpoint.
  void checkpoint() const { save_checkpoint(options_, names_, scales_, state_, t0_); }

 private:
  /// The paper's ε (eq. 2) and δ (eq. 3) at an accepted point: sets `reason` and `message` when LM stops.
  void verdict(const ceres::IterationSummary& s) {
    if (s.cost < options_.epsilon) {
      reason = Termination::objective_below_epsilon;
      message = "f = " + format_number(s.cost) + " < epsilon = " + format_number(options_.epsilon) + " (eq. 2)";
      return;
    }
    if (s.iteration == 0) return;
    // Eq. (3): the paper's t_i = ΔJ / J_i, element-wise.
    double t = 0;
    for (Eigen::Index k = 0; k < x_.size(); ++k) {
      const double dx = std::abs(x_(k) - x_prev_(k));
      t = std::max(t, x_prev_(k) != 0 ? dx / std::abs(x_prev_(k)) : dx);
    }
    if (t < options_.delta) {
      reason = Termination::step_below_delta;
      message = "relative step max|t| = " + format_number(t) + " < delta = " + format_number(options_.delta) + " (eq. 3)";
    }
  }

  /// The active set. A free variable is held on its bound when LM's step is blocked by it: the
  /// accepted step left it there, or the trial just rejected was projected onto it, and f decreases
  /// out of the box there (Ceres's projected steps would go on trying to leave: its model then
  /// promises what the projected step cannot give, and LM crawls or stalls). A held variable is
  /// released at any accepted point where f decreases into the box again; where LM stops on δ, that
  /// is its KKT test. A change ends this Ceres solve (held_changed); LM goes on in the next.
  void update_active_set(bool accepted) {
    if (!options_.active_set || reason == Termination::objective_below_epsilon) return;
    const Eigen::Index n = x_.size();
    // f decreases into the box again: free at once (LM goes on if it was stopping)
    if (accepted && !state_.held.empty() &&
        release_held(box_, x_, cost_.gradient(x_), options_.gradient_tolerance, names_, reporter_, state_.held)) {
      reason.reset();
      held_changed = true;
    }
    if (reason) return;  // LM stops here: the KKT test follows
    const Eigen::VectorXd& before = cost_.last_trial;  // the rejected step's candidate
    if (!accepted && before.size() != n) return;
    std::vector<Eigen::Index> candidates;
    for (Eigen::Index k = 0; k < n; ++k) {
      const bool lower = box_.at_lower(x_, k) && (accepted || box_.at_lower(before, k));
      const bool upper = box_.at_upper(x_, k) && (accepted || box_.at_upper(before, k));
      if ((lower || upper) && !std::binary_search(state_.held.begin(), state_.held.end(), static_cast<int>(k)))
        candidates.push_back(k);
    }
    if (candidates.empty()) return;
    const Eigen::VectorXd g = cost_.gradient(x_);
    if (g.size() != n) return;
    std::vector<std::string> newly;
    for (Eigen::Index k : candidates)
      if (box_.pushed_out(x_, g, k)) {
        state_.held.push_back(static_cast<int>(k));
        newly.push_back(names_[k]);
      }
    if (newly.empty()) return;
    std::sort(state_.held.begin(), state_.held.end());
    held_changed = true;
    reporter_.info("identify: held at its bound (f decreases out of the box): " + joined(newly));
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
  double step_test_norm_ = -1, step_test_delta_ = 0;  // continue_step_test; -1 = Ceres's test
  int base_iterations_;
  std::chrono::steady_clock::time_point t0_;
  const LmCost& cost_;
  const Box& box_;
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
      throw InputError(Location{"", 0, "identify.start"}, "one start value per parameter", std::to_string(n) + " values",
                       std::to_string(options.start->size()));
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

  IdentifyResult result;
  result.names = names;
  result.jacobian = options.jacobian;
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
  const bool cut_steps = options.barrier_growth > 0 && problem.has_lower_bound();
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
      record_start = true;
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
      if (monitor.held_changed) {  // LM goes on from the accepted point with the new active set
        x = state.x;
        record_start = false;
        continue;
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
      if (termination == Termination::fe_failure || summary.iterations.empty()) {
        if (message.empty()) message = summary.message;
        finish(Termination::fe_failure, message);
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
      finish(Termination::unstable, "the stability test still lowers f after " + std::to_string(state.restarts) + " restarts");
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
  result.wall_seconds = state.wall_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

int LevelsResult::evaluations() const {
  int n = coarse_evaluations;
  for (const IdentifyResult& r : levels) n += r.evaluations;
  return n;
}

namespace {

/// The coarse level's residuals corrected to the fine level's at `at`, to first order:
///     r̃(J) = r_c(J) + (r_f(at) − r_c(at)) + (∂r_f/∂J(at) − ∂r_c/∂J(at)) (J − at),
/// so r̃ and ∂r̃/∂J are the fine level's at `at`, and r̃ keeps the coarse model's curvature elsewhere
/// (space mapping; docs/theory.md §3.3).
class CorrectedProblem final : public Problem {
 public:
  CorrectedProblem(const Problem& coarse, Eigen::VectorXd at, const Evaluation& fine, const Evaluation& coarse_at)
      : coarse_(coarse), at_(std::move(at)), d_(fine.r - coarse_at.r), D_(fine.jacobian - coarse_at.jacobian) {}
  const std::vector<Parameter>& parameters() const override { return coarse_.parameters(); }
  int residuals() const override { return coarse_.residuals(); }
  Evaluation evaluate(const Eigen::VectorXd& J, bool jacobian) const override {
    Evaluation e = coarse_.evaluate(J, jacobian);
    if (!e.ok) return e;
    e.r += d_ + D_ * (J - at_);
    if (jacobian) e.jacobian += D_;
    return e;
  }
  double lower_bound(const Eigen::VectorXd& J) const override { return coarse_.lower_bound(J); }
  bool has_lower_bound() const override { return coarse_.has_lower_bound(); }
  bool keeps_simulations() const override { return coarse_.keeps_simulations(); }

 private:
  const Problem& coarse_;
  Eigen::VectorXd at_, d_;
  Eigen::MatrixXd D_;
};

/// A finer level from `start` by corrected coarse models (identify_by_levels): each outer iteration
/// evaluates the fine level with its Jacobian at c, minimises the coarse level corrected to it there
/// (LM, no stability test) and moves c to that minimum when the fine f decreases there. When it does
/// not, LM on the fine level itself takes over from c.
IdentifyResult corrected_level(const Problem& coarse, const Problem& fine, const Eigen::VectorXd& start,
                               const IdentifyOptions& options, const Reporter& reporter, int& coarse_evaluations) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto& params = fine.parameters();
  const auto n = static_cast<Eigen::Index>(params.size());
  Eigen::VectorXd scales(n);
  IdentifyResult r;
  for (Eigen::Index k = 0; k < n; ++k) scales(k) = params[k].resolved_scale(), r.names.push_back(params[k].name);
  r.start = start;
  r.jacobian = options.jacobian;
  IdentifyOptions sub = options;
  sub.stability_test = false, sub.on_checkpoint = {}, sub.initial_trust_region_radius = 1e4;
  const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  const JacobianOptions jo = options.jacobian_options();  // exact, or finite differences
  Eigen::VectorXd c = start;
  Evaluation e = evaluate(fine, c, true, jo);
  r.evaluations = e.evaluations, r.jacobian_evaluations = 1;
  if (!e.ok) {
    r.termination = Termination::fe_failure, r.message = "at the start point: " + e.message, r.parameters = c;
    r.wall_seconds = seconds();
    return r;
  }
  r.history.push_back({0, e.objective(), c, 0});
  bool done = false;
  while (!done && r.iterations < options.max_iterations) {
    if (e.objective() < options.epsilon) {
      r.termination = Termination::objective_below_epsilon;
      r.message = "f = " + format_number(e.objective()) + " < epsilon = " + format_number(options.epsilon) + " (eq. 2)";
      break;
    }
    const Evaluation at = evaluate(coarse, c, true, jo);
    coarse_evaluations += at.evaluations;
    if (!at.ok) break;  // LM on the fine level takes over
    sub.start = c;
    const IdentifyResult step = identify(CorrectedProblem(coarse, c, e, at), sub);
    coarse_evaluations += step.evaluations;
    ++r.iterations;
    const Evaluation next = evaluate(fine, step.parameters, true, jo);
    r.evaluations += next.evaluations, ++r.jacobian_evaluations;
    const double change = (step.parameters - c).cwiseQuotient(scales).cwiseAbs().maxCoeff();
    if (!next.ok || !(next.objective() < e.objective())) {  // no step that lowers the fine f: LM takes over
      ++r.failed_evaluations;
      break;
    }
    c = step.parameters, e = next;
    r.history.push_back({r.iterations, e.objective(), c, 0});
    reporter.report({"identify", static_cast<std::size_t>(r.iterations), 0,
                     "corrected coarse model: f = " + format_number(e.objective()) + ", largest change " + format_number(change)});
    if (change < options.delta) {
      r.termination = Termination::step_below_delta;
      r.message = "a corrected-model step changed no coefficient by more than delta = " + format_number(options.delta) +
                  " (relative, eq. 3)";
      done = true;
    }
  }
  if (!done && r.termination != Termination::objective_below_epsilon) {  // LM on the fine level from c
    sub.start = c;
    IdentifyResult lm = identify(fine, sub, reporter);
    lm.start = start;
    lm.iterations += r.iterations, lm.evaluations += r.evaluations, lm.jacobian_evaluations += r.jacobian_evaluations;
    lm.failed_evaluations += r.failed_evaluations;
    lm.history.insert(lm.history.begin(), r.history.begin(), r.history.end());
    lm.wall_seconds = seconds();
    return lm;
  }
  r.parameters = c;
  r.objective = e.objective();
  r.uncertainty = uncertainty(e.jacobian, e.r, c, scales, fine.residual_variance());
  r.residuals = e.r;
  r.wall_seconds = seconds();
  return r;
}

}  // namespace

LevelsResult identify_by_levels(const std::vector<const Problem*>& levels, const IdentifyOptions& options,
                                const Reporter& reporter) {
  const Location where{"", 0, "identify.levels"};
  if (levels.empty()) throw InputError(where, "no level to identify on", "one problem or more", "none");
  if (options.resume_from) throw InputError(where, "a checkpoint to resume a run by levels from", "none", "one");
  const auto same = [](const Parameter& a, const Parameter& b) {
    return a.name == b.name && a.resolved_scale() == b.resolved_scale() && a.lower == b.lower && a.upper == b.upper;
  };
  for (const Problem* p : levels) {
    const auto& a = p->parameters();
    const auto& b = levels.front()->parameters();
    if (a.size() != b.size() || !std::equal(a.begin(), a.end(), b.begin(), same))
      throw InputError(where, "levels that identify different parameters", "the same names, scales and bounds on every level",
                       "different ones");
  }
  LevelsResult out;
  for (size_t level = 0; level < levels.size(); ++level) {
    out.levels.push_back(level == 0 ? identify(*levels[0], options, reporter)
                                    : corrected_level(*levels[0], *levels[level], out.levels.back().parameters, options,
                                                      reporter, out.coarse_evaluations));
    out.wall_seconds += out.levels.back().wall_seconds;
    if (out.levels.back().termination == Termination::fe_failure) break;
  }
  out.result = out.levels.back();
  out.result.stability_passed = out.levels.front().stability_passed;  // the test ran there
  return out;
}

}  // namespace tricot::ident
