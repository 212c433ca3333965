// Levenberg–Marquardt identification (docs/theory.md §3, paper §2.1) on Ceres: the paper's ε (eq. 2) and
// δ (eq. 3) criteria, relative parameters, bounds, the stability test with restarts, covariance
// (§8), a checkpoint after every accepted step and resume from one.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tricot/core/options.hpp"
#include "tricot/core/progress.hpp"
#include "tricot/ident/covariance.hpp"
#include "tricot/ident/problem.hpp"

namespace tricot::ident {

enum class Termination {
  objective_below_epsilon,   ///< converged: f < ε (eq. 2)
  step_below_delta,          ///< converged: an accepted step below δ (eq. 3), Ceres' parameter
                             ///< tolerance on a trial step, or the trust region collapsed
  objective_stalled,         ///< converged: a trial step changed f by < function_tolerance · f
  gradient_below_tolerance,  ///< converged: gradient max-norm ≤ gradient_tolerance
  max_iterations,            ///< not converged: max_iterations LM iterations used
  unstable,                  ///< the stability test still found a lower f after max_restarts
  fe_failure,                ///< the model could not be evaluated at the start or at an accepted
                             ///< point (the FE did not converge), or LM stopped because every step
                             ///< it tried from the last accepted point failed; `message` has why
};
const char* to_string(Termination t);  ///< the enumerator's name

/// Where a run stands (checkpoint.json's "phase"): what a resumed run does next.
enum class Phase {
  lm,         ///< LM is under way: it goes on from the last accepted point
  stability,  ///< LM converged (termination, message): the stability test comes next
  done,       ///< finished (termination, message, stability_passed): only the uncertainty is left
};
const char* to_string(Phase p);                                ///< "lm", "stability", "done"
std::optional<Phase> phase_from_string(const std::string& s);  ///< the inverse; nullopt when unknown

/// One point of the history: the start, every accepted LM step, and every stability restart.
struct HistoryEntry {
  int iteration = 0;           ///< LM iterations so far (accepted and rejected, all restarts)
  double objective = 0;        ///< f, eq. (1)
  Eigen::VectorXd parameters;  ///< J
  int restart = 0;             ///< stability restarts before this entry
};

/// LM's progress at an accepted point, after the ε (eq. 2) and δ (eq. 3) tests were made there: all a
/// resumed run needs to go on along the same path (resume_from). Ceres's Levenberg–Marquardt state at
/// an accepted point is x and the radius (its radius-decrease factor is then back at 2 and no
/// diagonal is reused), so the resumed run takes the same steps. The library does not write it;
/// on_checkpoint hands it to the caller.
struct LmProgress {
  Eigen::VectorXd x;  ///< LM variables at the accepted point (exact, for the resume)
  double objective = 0;
  double trust_region_radius = 0;  ///< LM's radius for the next step (1/μ)
  int iterations = 0, evaluations = 0, jacobian_evaluations = 0, failed_evaluations = 0, restarts = 0;
  /// Stability-test trials rejected without the FE (Problem::lower_bound), not in `evaluations`.
  int skipped_evaluations = 0;
  double wall_seconds = 0;  ///< spent so far, carried on by a resumed run
  std::vector<HistoryEntry> history;
  Phase phase = Phase::lm;  ///< what comes next
  /// Phase stability or done: how LM (phase stability) or the run (done) ended, and why.
  Termination termination = Termination::fe_failure;
  std::string message;
  bool stability_passed = false;  ///< phase done: the last stability test found no lower f
  /// The active set: LM variables held at a bound (sorted), because f decreases out of the box there
  /// (the gradient points outward). LM steps in the others until it converges; then a held variable
  /// whose gradient points inward again is released (a KKT test).
  std::vector<int> held;
};

struct Checkpoint : LmProgress {
  std::vector<std::string> names;  ///< identified coefficients, in order
  Eigen::VectorXd scales;          ///< LM units: J = scales ∘ x
  Eigen::VectorXd parameters;      ///< J = scales ∘ x, for reading
};

struct IdentifyOptions {
  /// Eq. (2): stop when f < ε (absolute; f as eq. 1), ≥ 0; 0 = off. Paper: 1e-12.
  double epsilon = 1e-12;
  /// Eq. (3): stop when an accepted step changes no coefficient by more than δ relative,
  /// max_k |ΔJ_k| / |J_k| < δ (|ΔJ_k| / scale_k where J_k = 0); also Ceres' parameter_tolerance
  /// (‖Δx‖ ≤ δ(‖x‖ + δ) on a trial step). (0, 1). Paper: 1e-5.
  double delta = 1e-5;
  /// Stop when a trial step changes f by less than this fraction of f (Ceres' function_tolerance),
  /// [0, 1); 0 = off.
  double function_tolerance = 1e-12;
  /// Stop when the max-norm of the gradient of f in LM units is ≤ this (Ceres'), ≥ 0; 0 = off.
  double gradient_tolerance = 1e-14;
  /// LM iterations in all (accepted and rejected, restarts included), 1–100000.
  int max_iterations = 200;
  /// The paper's stability test: after convergence, evaluate f with each coefficient in turn scaled
  /// by (1 ± η) (± η·scale where it is 0); restart LM from the best if it is below f*.
  bool stability_test = true;
  double stability_eta = 0.05;  ///< η, (0, 1)
  int max_restarts = 10;        ///< stability restarts, 0–1000; more → termination `unstable`
  JacobianMode jacobian = JacobianMode::exact;
  Difference difference = Difference::forward;  ///< finite_difference only
  double fd_step = 1e-6;                        ///< finite_difference only: h_k = fd_step · scale_k, (0, 0.1]
  /// Threads for finite-difference columns and the stability test, 0–1024; 0 = OpenMP's default.
  int threads = 0;
  /// LM's first trust-region radius 1/μ₀ in LM units (relative), (0, 1e16]. A damped first step
  /// keeps a poor start from driving the FE into laws it cannot solve: on the clamped uniaxial
  /// Mooney–Rivlin test from ×2 the truth, 1e4 (Ceres' default, nearly Gauss–Newton) cost 107
  /// failed FE trials and 5 stability restarts, 10 none, 1 none but more iterations.
  double initial_trust_region_radius = 10;
  /// With bounds on the parameters, Ceres's projected Armijo line search along each LM step (its
  /// `max_num_line_search_step_size_iterations`). Each of its trials is an FE evaluation (without
  /// sensitivities, and interpolated on f alone, where the problem keeps its simulations), but its
  /// backtracking is what saves LM's long steps that fail in the FE: on the §4 campaign LM without it
  /// was still at f = 1.59 after 74 iterations (each failure shrinks the radius, and the short damped
  /// steps run into cliffs of f), with it at 0.39 after 2.
  bool bounds_line_search = true;
  /// The most trial points of that line search per LM step, 1–100 (Ceres's default 20). Each is an
  /// FE evaluation: on the §4 campaign a step LM rejects in the end cost 12–13 of
  /// them at 20, 5 at 4, with the same accepted points (CHANGELOG.md, issue 12).
  int line_search_trials = 20;
  /// With bounds: an active set (docs/validation.md §5). A coefficient
  /// that a rejected LM step was projected onto its bound, with f decreasing out of the box, is held
  /// there (Ceres's SubsetManifold) and released where f decreases into the box. Off: Ceres's projected
  /// steps alone. On the 110 mm campaign it saves 3 stability restarts (285 → 124 evaluations); on
  /// the demo's chain it leads LM to another path that walls in at element 107, so it is opt-in.
  bool active_set = false;
  /// With a problem whose f has a part that needs no FE (Problem::lower_bound: the stability
  /// barrier), the most that part may grow along one LM step, as a fraction of f at the accepted
  /// point, [0, 1); 0 = off. Each step (and each trial of its line search) is cut, along its
  /// direction, where the barrier would grow more (bisection on the barrier alone). The barrier's rows
  /// are zero at the accepted point, so LM's model does not see them: on the §4 campaign its steps
  /// ran deep into them, where f is certain to be higher and the FE often fails; cut, the 110 mm
  /// identification reaches the same f from any start within ±1 % (uncut: 1 % apart, or walled in)
  /// in 52–78 FE evaluations instead of 63–213 (docs/validation.md §5: steps cut at the
  /// stability barrier").
  double barrier_growth = 0.01;
  /// Called with the state to save after every accepted step (and at the start), once its ε and δ
  /// tests are made, when LM stops (phase stability or done) and after each stability test; may be
  /// empty.
  std::function<void(const Checkpoint&)> on_checkpoint;
  /// Continue a run from its last checkpoint: LM goes on from the same state (or the stability test
  /// or the end, by its phase), so it reaches the same answer with the same iteration count. Its
  /// names and scales must match the problem's (InputError `resume`).
  std::optional<Checkpoint> resume_from;
  /// J to start from instead of the parameters' start values (one value per parameter), e.g. a coarser
  /// model's answer (identify_by_levels). Not with resume_from, whose point it would replace.
  std::optional<Eigen::VectorXd> start;

  /// The config keys of [identify] these options hold (core/options.hpp).
  static auto keys() {
    using O = IdentifyOptions;
    return std::tuple{
        option(&O::epsilon, "identify.epsilon", "Eq. (2): stop when f < epsilon; 0 = off. Paper: 1e-12.", 0, 1),
        option(&O::delta, "identify.delta",
               "Eq. (3): stop when an accepted step changes no coefficient by more than delta (relative),\n"
               "in (0, 1). Paper: 1e-5.",
               0, 1),
        option(&O::function_tolerance, "identify.function_tolerance",
               "Stop when a step changes f by less than this fraction of f; 0 = off.", 0, 1),
        option(&O::gradient_tolerance, "identify.gradient_tolerance",
               "Stop when the gradient's max-norm (LM units) is below this; 0 = off.", 0, 1e12),
        option(&O::max_iterations, "identify.max_iterations",
               "LM iterations in all (accepted and rejected, stability restarts included).", 1, 100000),
        option(&O::stability_test, "identify.stability_test",
               "The paper's stability test: after convergence, f with each coefficient scaled by (1 ± eta);\n"
               "LM restarts from a lower one."),
        option(&O::stability_eta, "identify.stability_eta", "η of the stability test, in (0, 1).", 0, 1),
        option(&O::max_restarts, "identify.max_restarts",
               "Stability restarts before giving up (termination `unstable`).", 0, 1000),
        option(&O::jacobian, "identify.jacobian",
               "exact: from the FE sensitivities (docs/theory.md §7). finite_difference: one perturbed FE run per\n"
               "coefficient (two when central), in parallel threads (the paper's way).",
               {{JacobianMode::exact, "exact"}, {JacobianMode::finite_difference, "finite_difference"}}),
        option(&O::difference, "identify.difference", "finite_difference only: forward or central.",
               {{Difference::forward, "forward"}, {Difference::central, "central"}}),
        option(&O::fd_step, "identify.fd_step", "finite_difference only: step h_k = fd_step · scale_k, in (0, 0.1].", 0,
               0.1),
        option(&O::threads, "identify.threads",
               "Threads for tests and finite-difference columns; 0 = all cores; more than the cores run as many as "
               "the cores.",
               0, 1024),
        option(&O::initial_trust_region_radius, "identify.initial_trust_region_radius",
               "LM's first trust-region radius (1/μ₀, LM units), > 0.", 0, 1e16),
        option(&O::line_search_trials, "identify.line_search_trials",
               "With bounds: the most trial points of the projected line search along each LM step (each one\n"
               "FE evaluation).",
               1, 100),
        option(&O::active_set, "identify.active_set",
               "With bounds: hold a coefficient on its bound when an LM step was projected onto it and f\n"
               "decreases out of the box there, release it where f decreases into the box (the log names\n"
               "each). false: Ceres's projected steps alone, which can stall on a bound. See docs/validation.md."),
        option(&O::barrier_growth, "identify.barrier_growth",
               "With [stability]: the most the barrier's part of f may grow along one LM step, as a fraction of\n"
               "f at the accepted point; each step is cut along its direction where it would grow more (the\n"
               "barrier needs no FE). 0 = off. See docs/validation.md §5.",
               0, 1)};
  }
  /// Throws InputError naming `identify.<field>`: the ranges keys() declares, and the open ends that
  /// a declared (closed) range cannot say.
  void validate() const;
  JacobianOptions jacobian_options() const { return {jacobian, difference, fd_step, threads}; }
};

struct IdentifyResult {
  Termination termination = Termination::fe_failure;
  std::string message;  ///< one line: why it stopped
  std::vector<std::string> names;
  Eigen::VectorXd start;       ///< J at the start (of this run, or of the resumed one)
  Eigen::VectorXd parameters;  ///< J*, the lowest f found
  double objective = 0;        ///< f(J*)
  Uncertainty uncertainty;     ///< at J* (empty when J* could not be evaluated with a Jacobian)
  /// r(J*), the scaled residuals (eq. 1; a stability barrier's rows after the data's), when J* was
  /// evaluated: each data group's share of f.
  Eigen::VectorXd residuals;
  int iterations = 0;            ///< LM iterations (accepted and rejected), restarts included
  int evaluations = 0;           ///< r(J) computations: trials, finite-difference columns, stability
  int jacobian_evaluations = 0;  ///< Jacobians LM used
  int failed_evaluations = 0;    ///< trial points where the model failed (steps rejected)
  /// Stability-test trials rejected without the FE: the part of f that needs none (the stability
  /// barrier) already reached the f* they had to beat (Problem::lower_bound).
  int skipped_evaluations = 0;
  int restarts = 0;               ///< stability restarts
  bool stability_passed = false;  ///< the last stability test found no lower f
  double wall_seconds = 0;
  JacobianMode jacobian = JacobianMode::exact;
  std::vector<HistoryEntry> history;

  /// Converged by one of the four criteria and (when asked) passed the stability test.
  bool converged() const;
  std::vector<double> std_error() const;  ///< uncertainty.std_error as a list
  /// One line, as Ceres's Summary::BriefReport(): "converged: step_below_delta after 12 LM iterations,
  /// 15 evaluations, 2.3 s (MESSAGE), f = 1.234e-13" ("NOT converged: ..." otherwise).
  std::string brief_report() const;
};

/// Runs LM from the parameters' start values (or options.resume_from). Validates the options and
/// parameters first (InputError); a model that fails is a termination, never an exception.
/// Progress: one report per LM iteration, stage "identify", detail "f = …, C10 = …, …".
IdentifyResult identify(const Problem& problem, const IdentifyOptions& options = {}, const Reporter& reporter = {});

/// An identification by mesh levels (docs/theory.md §3.3).
struct LevelsResult {
  /// The finest level's run: the answer, f, its uncertainty; stability_passed: the first level's.
  IdentifyResult result;
  /// Every level's run, coarse to fine (the last is `result`). A finer level's iterations are its
  /// corrected-model steps (then LM's, if it took over) and its evaluations are its own.
  std::vector<IdentifyResult> levels;
  int coarse_evaluations = 0;  ///< the first level's evaluations inside the finer levels' corrected models
  double wall_seconds = 0;     ///< all levels together
  int evaluations() const;     ///< FE evaluations of all levels together, the corrected models' included
};

/// LM on the same tests meshed ever finer (`levels`, coarse to fine). The first level runs LM from
/// the parameters' start (or options.start) with the paper's stability test. Every finer level starts
/// from the answer before it and is solved through the first level corrected to it (space mapping;
/// docs/theory.md §3.3). At its current point c:
/// - it is evaluated once with its Jacobian;
/// - the first level's residuals are shifted to match its r and ∂r/∂J at c;
/// - LM minimises that corrected coarse problem (cheap), and c moves to its minimum when the fine f
///   decreases there.
/// The coarse model carries the curvature that LM's linear model lacks, so a few fine evaluations
/// reach the fine optimum (the paper-scale identification: 4 at 24 874 dofs, where LM alone took 37).
/// Stops on ε (eq. 2) and δ (eq. 3) as LM does. Where a corrected step does not lower f, LM on the
/// fine level itself goes on from c. A level that ends in fe_failure ends the run. The levels must
/// identify the same parameters (names, scales and bounds; InputError `identify.levels`), and
/// resume_from is refused (InputError `identify.levels`).
LevelsResult identify_by_levels(const std::vector<const Problem*>& levels, const IdentifyOptions& options = {},
                                const Reporter& reporter = {});

}  // namespace tricot::ident
