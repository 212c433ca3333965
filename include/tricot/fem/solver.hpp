// Nonlinear quasi-static solution of a test model (docs/theory.md §4–§7): total-Lagrangian assembly, Newton–
// Raphson with the consistent tangent and a line search, load stepping with automatic cutback, a
// sparse direct solver (Eigen's SimplicialLDLT or CHOLMOD; for non-symmetric tangents a simplicial LU
// on node blocks below 60 000 unknowns, UMFPACK above or where that LU meets a tiny pivot) whose
// symbolic analysis is kept across iterations and steps, and exact sensitivities du/dc by
// back-substitution with the converged tangent.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "tricot/core/options.hpp"
#include "tricot/core/progress.hpp"
#include "tricot/fem/law.hpp"
#include "tricot/fem/model.hpp"

namespace tricot::fem {

/// Sparse direct solver for symmetric tangents (docs/theory.md §4): a factorization on a fill-reducing
/// ordering computed once per simulation. Non-symmetric tangents: with eigen_ldlt, and with automatic
/// below 60 000 unknowns, a simplicial LU without pivoting on 2 × 2 node blocks (UMFPACK where a pivot
/// is tiny); otherwise, and for LDLᵀ breakdowns, UMFPACK LU.
enum class LinearSolverKind {
  /// By size, on the crossover measured by bench/linear_solver_benchmark.cpp (docs/validation.md,
  /// issue 15): eigen_ldlt for small tangents, cholmod_supernodal for large ones.
  automatic,
  eigen_ldlt,    ///< Eigen's SimplicialLDLT on an AMD ordering: fastest below the crossover
  cholmod_ldlt,  ///< SuiteSparse CHOLMOD's simplicial LDLᵀ
  /// CHOLMOD's supernodal LLᵀ (BLAS on dense supernodes) on a METIS nested-dissection ordering; a
  /// tangent that is not positive definite is factorized by CHOLMOD's simplicial LDLᵀ instead.
  cholmod_supernodal,
};

struct SolveOptions {
  /// Newton stops when ‖R_free‖ ≤ tolerance · max(‖F_reactions‖, 1e-12 N), > 0.
  double tolerance = 1e-10;
  /// Newton iterations per (sub)step, 1–200.
  int max_iterations = 25;
  /// Backtracking line search on the residual norm (off = full Newton steps).
  bool line_search = true;
  /// Halvings of a step that failed before giving up, 0–30.
  int max_cutbacks = 8;
  /// Compute du/dc and d(edge force)/dc at every step (docs/theory.md §7).
  bool sensitivities = false;
  /// Keep every Newton iteration's residual norm in StepResult::residuals.
  bool keep_residuals = true;
  /// Sparse solver for symmetric tangents (see LinearSolverKind).
  LinearSolverKind linear_solver = LinearSolverKind::automatic;
  /// When set, asked before every (sub)step increment: true stops the run there with
  /// SolveTermination::cancelled (e.g. an identification whose evaluation already failed in another
  /// test: its result is discarded anyway). Called from the simulating thread; must be thread-safe.
  std::function<bool()> cancelled;
  /// A converged run of the same test, with sensitivities, under a nearby law to start from (an
  /// identification's last evaluation with a Jacobian), or null (a run without sensitivities is
  /// ignored: its states start Newton further off than the load path's predictor); it must outlive
  /// the call. Each step's Newton starts from this run's last converged state moved by that run's
  /// increment to the step (its states moved by du/dc · warm_start_dc) instead of the predictor along
  /// the load path, and the rig's setting is made in one increment to that run's set state (then
  /// SimulationResult::setting holds that one state). After its first Newton
  /// iteration such a step keeps the tangent's factorization while the residual falls 10× an
  /// iteration (chord steps), and it takes the load path when it has not converged in 5. The
  /// states are the same to the tolerance, not bit for bit.
  const struct SimulationResult* warm_start = nullptr;
  /// The law's coefficients now minus those of warm_start's run (all of them, in the law's order).
  Eigen::VectorXd warm_start_dc;

  /// The config keys of [solver] (core/options.hpp); the other members are set in code.
  static auto keys() {
    using O = SolveOptions;
    return std::tuple{
        option(&O::tolerance, "solver.tolerance",
               "Newton stops when the free residual ≤ tolerance × the reaction force, > 0.", 0, 1),
        option(&O::max_iterations, "solver.max_iterations", "Newton iterations per (sub)step.", 1, 200),
        option(&O::line_search, "solver.line_search", "Backtracking line search on the residual norm."),
        option(&O::max_cutbacks, "solver.max_cutbacks", "Halvings of a failed step before giving up.", 0, 30)};
  }
  /// Throws InputError naming `solver.<field>` when out of range.
  void validate() const;
};

/// The converged state at one step of the list.
struct StepResult {
  double load = 0;               ///< the step's load as given (mm or N)
  Eigen::VectorXd u;             ///< nodal displacements, dof 2n = u_x, 2n+1 = u_y (mm)
  double edge_displacement = 0;  ///< u_y of the grip (mm, quarter model; any mesh: of the force boundary)
  /// Full-specimen grip force: 2 × the quarter's reaction (N); any mesh: TestModel::force_scale × the
  /// force boundary's resultant along TestModel::force_component.
  double edge_force = 0;
  double force_per_width = 0;  ///< edge_force / full initial width (N/mm)
  double side_force = 0;       ///< full-specimen reaction on the guide (N, 0 when free)
  /// Resultant internal force (N) of each boundary of TestModel::resultant_boundaries(), in order:
  /// the force the specimen exerts on what holds it there (the reaction is its opposite).
  std::vector<Vec2> resultants;
  int iterations = 0;             ///< Newton iterations, summed over sub-steps
  int cutbacks = 0;               ///< sub-steps inserted before this step converged
  std::vector<double> residuals;  ///< ‖R‖ per Newton iteration of the last sub-step
  /// Sensitivities (when asked): du_dc.col(k) = ∂u/∂c_k, and ∂edge_force/∂c_k.
  Eigen::MatrixXd du_dc;
  Eigen::VectorXd dforce_dc;
  /// For a force-controlled grip, d(edge_displacement)/dc (du_dc holds it too, at a top node).
};

enum class SolveTermination {
  converged,      ///< every step converged
  not_converged,  ///< a step failed after max_cutbacks halvings; `steps` holds the converged ones
  /// an element inverted (det F ≤ 0 at a quadrature point), the law returned a non-finite value, or
  /// a force-controlled grip converged only to a compressed state (grip displacement ≤ 0 under a
  /// tensile force: the law has no tensile equilibrium there), after every cutback
  invalid_state,
  cancelled,  ///< SolveOptions::cancelled returned true; `steps` holds the converged ones
};
const char* to_string(SolveTermination t);

struct SimulationResult {
  SolveTermination termination = SolveTermination::converged;
  std::string message;            ///< one line: what happened, which step failed and why
  std::vector<StepResult> steps;  ///< one per converged load step, in order
  /// The rig's setting increments (TestModel::guide_setting_steps), before `steps`: the states with
  /// the grip at rest as the guide moves to its setting (u and the forces; no sensitivities).
  std::vector<StepResult> setting;
  double seconds = 0;                ///< wall time
  double factorization_seconds = 0;  ///< of which in numeric factorization
  int factorizations = 0;
  bool usable() const { return termination == SolveTermination::converged; }
  /// One line: "21 steps, 38 Newton iterations, 0 cutbacks, 781 ms; final force 34.443 N (0.31312 N/mm)
  /// at 30.676 mm" (iterations and cutbacks of the steps), or "no step converged, 781 ms".
  std::string brief_report() const;
};

/// Runs every step of `test` with `law`. Validates options and model first (InputError); a step that
/// does not converge is a status in the result, never an exception. Progress: one report per step.
SimulationResult simulate(const TestModel& test, const Law& law, const SolveOptions& options = {},
                          const Reporter& reporter = {});

/// Below this many unknowns simulate()'s sensitivities of a non-symmetric tangent factorize the
/// converged tangent anyway, so add_sensitivities costs no more than they do; above, they are refined
/// on Newton's last factorization, and add_sensitivities costs a factorization per step more (the
/// paper-scale evaluation, 24 874 dofs: 17.7 s against 12.2 s wall, bench/knit_campaign_benchmark.cpp).
constexpr Eigen::Index kSensitivitiesAfterBelow = 2000;

/// The sensitivities (StepResult::du_dc, dforce_dc) of a usable `result` of simulate(test, law,
/// options) run without them, computed afterwards from its converged states: per step, the tangent
/// and ∂R/∂c there, one factorization and one multi-column solve (the arithmetic of simulate() with
/// SolveOptions::sensitivities, which also reuses that factorization for its next predictor). The
/// Newton solves are not repeated. False, with result's termination and message set, when a state
/// cannot be evaluated; false and untouched when `result` is not usable.
bool add_sensitivities(const TestModel& test, const Law& law, SimulationResult& result,
                       const SolveOptions& options = {});

}  // namespace tricot::fem
