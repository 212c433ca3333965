// The pieces of the LM run (identify.cpp; docs/theory.md §3), each in its own file: the cost
// function that holds the whole residual vector (lm_cost.cpp), the active set and the cut steps
// (active_set.cpp), the monitor that applies the paper's ε and δ and writes checkpoints (monitor.cpp).
// Private to ident.
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tricot/ident/identify.hpp"

namespace tricot::ident::detail {

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

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// The evaluation at x (from the recent ones when possible), or nullptr when the model fails there.
  const Evaluation* at(const Eigen::VectorXd& x, bool jacobian) const;

  /// ∂f/∂x at x (f = ½ r·r, LM units) from the evaluation with the Jacobian there (cached at an
  /// accepted point); empty when the model fails at x.
  Eigen::VectorXd gradient(const Eigen::VectorXd& x) const;

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
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  /// At δ = 0 the step is whole (the fraction is 1 for short enough steps): the free variables' selection.
  bool PlusJacobian(const double*, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double*, double* jacobian) const override;

 private:
  int n_;
  std::vector<int> free_;
  Fraction fraction_;
};

/// The largest share t ∈ [0, 1] of the step d from x (LM units) along which the problem's FE-free
/// part of f (Problem::lower_bound) grows by at most `allowance`: 1 when the whole step keeps within
/// it, else found by bisection (to 2⁻⁴⁰ of the step).
double step_fraction(const Problem& problem, const Eigen::VectorXd& scales, const Eigen::VectorXd& x,
                     const Eigen::VectorXd& d, double allowance);

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

/// "a, b, c": the names of a log line.
std::string joined(const std::vector<std::string>& v);

/// The active set's release: the held variables whose gradient at x points into the box (beyond
/// `tolerance`) are freed and named in the log. At a point where LM stopped, this is the KKT test of a
/// bound-constrained minimum. Returns whether any was freed (none where the model fails at x).
bool release_held(const Box& box, const Eigen::VectorXd& x, const Eigen::VectorXd& g, double tolerance,
                  const std::vector<std::string>& names, const Reporter& reporter, std::vector<int>& held);

/// Ceres's message for its parameter tolerance, for the test a resumed run makes itself (Monitor).
std::string step_test_message(double step_norm, double x_norm, double delta);

/// Hands the state to on_checkpoint (wall time: the resumed runs' and this one's).
void save_checkpoint(const IdentifyOptions& options, const std::vector<std::string>& names,
                     const Eigen::VectorXd& scales, const State& state, std::chrono::steady_clock::time_point t0);

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

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override;

  /// Writes the state (progress and phase) through on_checkpoint.
  void checkpoint() const { save_checkpoint(options_, names_, scales_, state_, t0_); }

 private:
  /// The paper's ε (eq. 2) and δ (eq. 3) at an accepted point: sets `reason` and `message` when LM stops.
  void verdict(const ceres::IterationSummary& s);

  /// The active set. A free variable is held on its bound when LM's step is blocked by it: the
  /// accepted step left it there, or the trial just rejected was projected onto it, and f decreases
  /// out of the box there (Ceres's projected steps would go on trying to leave: its model then
  /// promises what the projected step cannot give, and LM crawls or stalls). A held variable is
  /// released at any accepted point where f decreases into the box again; where LM stops on δ, that
  /// is its KKT test. A change ends this Ceres solve (held_changed); LM goes on in the next.
  void update_active_set(bool accepted);

  void report(int iteration, const ceres::IterationSummary& s) const;

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

}  // namespace tricot::ident::detail
