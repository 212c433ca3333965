// After each LM iteration: the paper's ε (eq. 2) and δ (eq. 3), the history, the checkpoint and the
// progress line (lm.hpp).
#include "lm.hpp"

#include <algorithm>
#include <cstdio>

#include "tricot/core/error.hpp"

namespace tricot::ident::detail {

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

ceres::CallbackReturnType Monitor::operator()(const ceres::IterationSummary& s) {
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

void Monitor::verdict(const ceres::IterationSummary& s) {
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

void Monitor::update_active_set(bool accepted) {
  if (!options_.active_set || reason == Termination::objective_below_epsilon) return;
  const Eigen::Index n = x_.size();
  // f decreases into the box again: free at once (LM goes on if it was stopping)
  if (accepted && !state_.held.empty() &&
      release_held(box_, x_, cost_.gradient(x_), options_.gradient_tolerance, names_, reporter_, state_.held)) {
    reason.reset();
    held_changed = true;
  }
  if (reason) return;                                // LM stops here: the KKT test follows
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

void Monitor::report(int iteration, const ceres::IterationSummary& s) const {
  std::string detail = "f = " + format_number(state_.objective);
  if (s.iteration > 0 && !s.step_is_successful) detail += " (step rejected)";
  for (size_t k = 0; k < names_.size(); ++k)
    detail += ", " + names_[k] + " = " + format_number(scales_(k) * state_.x(k));
  reporter_.report({"identify", static_cast<size_t>(iteration), static_cast<size_t>(options_.max_iterations), detail});
}

}  // namespace tricot::ident::detail
