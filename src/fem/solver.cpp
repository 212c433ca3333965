// Quasi-static solution of a test model (docs/theory.md §4–§7): load stepping with cutback, Newton–Raphson with
// the consistent tangent and a backtracking line search, reactions, and exact sensitivities.
#include "tricot/fem/solver.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "assembly.hpp"
#include "linear_solver.hpp"
#include "tricot/fem/element.hpp"
#include "tricot/core/error.hpp"
#include "tricot/core/format.hpp"

namespace tricot::fem {

void SolveOptions::validate() const {
  check_ranges(*this);
  if (!(tolerance > 0))  // the declared range includes its ends: Newton needs a tolerance above 0
    throw InputError(Location{"", 0, "solver.tolerance"}, "out of range", std::to_string(tolerance), "> 0");
}

namespace {
// The unknowns of displacements u (a StepResult's u or a column of its du_dc).
Eigen::VectorXd unknowns(const detail::DofMap& dofs, const Eigen::Ref<const Eigen::VectorXd>& u) {
  Eigen::VectorXd z = Eigen::VectorXd::Zero(dofs.equations);
  for (size_t d = 0; d < dofs.eq.size(); ++d)
    if (dofs.eq[d] >= 0) z(dofs.eq[d]) = u(static_cast<Eigen::Index>(d));
  return z;
}
}  // namespace

const char* to_string(SolveTermination t) {
  switch (t) {
    case SolveTermination::converged: return "converged";
    case SolveTermination::not_converged: return "not_converged";
    case SolveTermination::invalid_state: return "invalid_state";
    case SolveTermination::cancelled: return "cancelled";
  }
  return "?";
}

std::string SimulationResult::brief_report() const {
  if (steps.empty()) return "no step converged, " + format_duration(seconds);
  int iterations = 0, cutbacks = 0;
  for (const StepResult& s : steps) iterations += s.iterations, cutbacks += s.cutbacks;
  const StepResult& last = steps.back();
  char tail[160];
  std::snprintf(tail, sizeof tail, "; final force %.5g N (%.5g N/mm) at %.5g mm", last.edge_force, last.force_per_width,
                last.edge_displacement);
  return std::to_string(steps.size()) + " steps, " + std::to_string(iterations) + " Newton iterations, " +
         std::to_string(cutbacks) + " cutbacks, " + format_duration(seconds) + tail;
}

namespace {

using detail::Assembled;
using detail::Load;

constexpr double kRefinedResidual = 1e-13;  // ‖b − K x‖/‖b‖ per column: round-off (the floor is ~1e-14)
constexpr int kRefineSweeps = 3;
constexpr size_t kHistory = 2;  // converged states the predictor extrapolates from, besides the last
// Iterations a warm start may take (SolveOptions::warm_start) before the step takes the load path
// instead: one Newton iteration, then chord iterations on its factorization. A start close to the
// solution converges within them at one factorization a step; one that does not would cost more
// than the load path's 1–2 factorizations.
constexpr int kWarmIterations = 5;
constexpr double kChordContraction = 0.1;  // chord steps go on while ‖R‖ falls 10× an iteration

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

/// Why a (sub)step failed.
struct Failure {
  /// The increment's own starting state (last solution, new boundary values) has an inverted element
  /// or a non-finite law value: no iteration can start. Trial states that invert during the
  /// iterations are a convergence failure instead (Newton wandered off, e.g. past a limit point).
  bool invalid = false;
  std::string why;
  bool cancelled = false;  ///< SolveOptions::cancelled said stop
  int element = -1;        ///< the element `why` names (inverted or non-finite), or −1
};

SolveTermination termination(const Failure& fail) {
  if (fail.cancelled) return SolveTermination::cancelled;
  return fail.invalid ? SolveTermination::invalid_state : SolveTermination::not_converged;
}

class Simulation {
 public:
  Simulation(const TestModel& test, const Law& law, const SolveOptions& options, const Reporter& reporter)
      : test_(test), law_(law), options_(options), reporter_(reporter), dofs_(detail::make_dof_map(test)),
        assembler_(test, dofs_, law), linear_solver_(assembler_.pattern(), options.linear_solver),
        coefficient_count_(static_cast<int>(law.coefficients().size())) {}

  SimulationResult run();
  /// The sensitivities of `result`'s steps (run without them), from their converged states: the
  /// arithmetic of run() with SolveOptions::sensitivities. False, with result's termination and
  /// message set, when a state cannot be evaluated or its tangent is singular.
  bool add_sensitivities(SimulationResult& result);

 private:
  bool step_sensitivities(StepResult& step, Failure& fail);
  Load load_at(size_t k) const;
  bool evaluate(const Eigen::VectorXd& z, const Load& L, bool tangent = true, bool sensitivities = false);
  bool linear_solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x, Failure& fail, bool refine = false);
  Eigen::VectorXd free_residual(const Load& L) const;
  double reaction_norm(const Load& L) const;
  double reference_force(const Load& L) const;
  bool factorize(Failure& fail);
  bool newton(const Load& from, const Load& to, StepResult& step, Failure& fail);
  bool iterate(Eigen::VectorXd z, const Load& to, StepResult& step, Failure& fail, int max_iterations,
               bool chord = false);
  bool warm_step(const Load& to, const Eigen::VectorXd& z_start, StepResult& step);
  Eigen::VectorXd warm_state(const StepResult& previous) const;
  bool solve_step(const Load& target, StepResult& step, Failure& fail);
  bool set_transverse_dimension(Failure& fail, std::string& where, std::vector<StepResult>& states);
  void record(const Load& L, StepResult& step);
  /// The measured force over the force boundary's summed internal force: 2 for the quarter model's
  /// grip (the other half of the specimen), TestModel::force_scale for a model of any mesh.
  double force_scale() const { return test_.has_conditions() ? test_.force_scale : 2.0; }
  std::string describe_element_failure() const;
  std::string describe_largest_residual(const Eigen::VectorXd& R) const;
  std::string ellipticity_note(int element) const;

  const TestModel& test_;
  const Law& law_;
  const SolveOptions& options_;
  const Reporter& reporter_;
  detail::DofMap dofs_;
  detail::Assembler assembler_;
  detail::LinearSolver linear_solver_;
  int coefficient_count_;
  Assembled assembled_;          // the last assembly
  bool factor_current_ = false;  // the factorization is of assembled_.K (else of an earlier, nearby state)
  bool tangent_fresh_ = false;   // assembled_.K is the tangent at the last evaluated state (else at an earlier one)
  Eigen::VectorXd u_;            // node displacements of the last assembly
  Eigen::VectorXd z_;            // converged unknowns
  Load load_;                    // converged load
  /// Converged states before z_ (newest last, at most kHistory), for the predictor's curvature.
  struct State {
    Load load;
    Eigen::VectorXd z;
    Eigen::VectorXd dz_ds;  // tangent per unit length of the load path (d, F, c); empty: unknown
  };
  std::vector<State> history_;
  Eigen::VectorXd tangent_next_;  // dz/ds at z_, computed by the predictor of the increment from it
  double peak_reaction_ = 0;      // the largest reaction norm of a converged state so far
};

Load Simulation::load_at(size_t k) const {
  Load L;
  if (test_.has_conditions()) {  // the boundary series' own values at step k
    L.t = static_cast<double>(k + 1);
    return L;
  }
  const double v = test_.loads[k];
  (test_.control == GripControl::displacement ? L.d : L.F) = v;
  if (test_.side == SideEdge::guide) {
    if (test_.guide_setting_steps > 0) L.c = test_.guide[0];  // set first, then held
    else L.c = test_.guide.size() == 1 ? test_.guide[0] * v / test_.loads.back() : test_.guide[k];
  }
  return L;
}

bool Simulation::evaluate(const Eigen::VectorXd& z, const Load& L, bool tangent, bool sensitivities) {
  detail::expand(dofs_, z, L, u_);
  LawRequest req;
  req.tangent = tangent;
  req.sensitivities = sensitivities;
  if (tangent) factor_current_ = false;
  tangent_fresh_ = tangent;
  return assembler_.assemble(u_, req, assembled_, L);
}

// K(assembled_) x = b (b may have several columns), factorizing assembled_.K unless the factorization is of it. With
// `refine`, a factorization of a nearby tangent (the last Newton iterate's) is tried first: iterative
// refinement x += K_old⁻¹ (b − K x) until every column's residual is at round-off, when it gets there
// within kRefineSweeps sweeps (each a solve and a product with K: with one column ~1/6 of a
// factorization of the 810-dof rig tangent, with the sensitivities' 14 columns ~3/4 of one).
bool Simulation::linear_solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& x, Failure& fail, bool refine) {
  if (refine && !factor_current_ && linear_solver_.factorizations > 0) {
    const Eigen::VectorXd nb = b.colwise().norm();
    Eigen::MatrixXd r, dx;
    linear_solver_.solve(b, x);
    double before = 1;  // the worst relative residual of the sweep before (of x = 0 at the first)
    for (int sweep = 0; sweep <= kRefineSweeps && x.allFinite(); ++sweep) {
      detail::residual(assembled_.K, b, x, r);
      double worst = 0;
      for (Eigen::Index j = 0; j < r.cols(); ++j) worst = std::max(worst, r.col(j).norm() / std::max(nb(j), 1e-300));
      if (worst <= kRefinedResidual) return true;
      // Sweeps contract the residual by about worst / before each: give up as soon as that rate
      // cannot reach round-off within kRefineSweeps (a chord step's far factorization).
      if (sweep == kRefineSweeps || !(worst < before) ||
          sweep + std::log(kRefinedResidual / worst) / std::log(worst / before) > kRefineSweeps)
        break;
      before = worst;
      linear_solver_.solve(r, dx);
      x += dx;
    }
  }
  if (!factor_current_ && !factorize(fail)) return false;
  linear_solver_.solve(b, x);
  if (!x.allFinite()) {
    fail.why = "the tangent is singular";
    return false;
  }
  return true;
}

// R_f = Σ f_int over each equation's dofs − the quarter's share F/2 of the grip force (docs/theory.md §6).
Eigen::VectorXd Simulation::free_residual(const Load& L) const {
  Eigen::VectorXd R = Eigen::VectorXd::Zero(dofs_.equations);
  for (size_t k = 0; k < dofs_.eq.size(); ++k)
    if (dofs_.eq[k] >= 0) R(dofs_.eq[k]) += assembled_.f(k);
  if (dofs_.master >= 0) R(dofs_.master) -= 0.5 * L.F;
  return R;
}

// The force that Newton's tolerance is relative to. A displacement path may come back toward zero (a
// lab record's unloading, or a boundary series), where the reactions vanish: there the largest reaction
// of the run's converged states sets the scale.
double Simulation::reference_force(const Load& L) const { return std::max({reaction_norm(L), peak_reaction_, 1e-12}); }

double Simulation::reaction_norm(const Load& L) const {
  double s = dofs_.master >= 0 ? 0.25 * L.F * L.F : 0.0;
  for (size_t k = 0; k < dofs_.eq.size(); ++k)
    if (dofs_.eq[k] < 0) s += assembled_.f(k) * assembled_.f(k);
  return std::sqrt(s);
}

bool Simulation::factorize(Failure& fail) {
  factor_current_ = linear_solver_.factorize(assembled_.K, assembled_.symmetric);
  if (factor_current_) return true;
  fail.why = "the tangent is singular";
  return false;
}

// Where a stalled Newton's residual sits: the node whose free dofs carry the largest part of it.
std::string Simulation::describe_largest_residual(const Eigen::VectorXd& R) const {
  const int nodes = test_.mesh.nodes();
  int worst = -1;
  double largest = -1;
  for (int n = 0; n < nodes; ++n) {
    double s = 0;
    for (int i = 0; i < 2; ++i)
      if (const int q = dofs_.eq[std::size_t(2 * n + i)]; q >= 0) s += R(q) * R(q);
    if (s > largest) largest = s, worst = n;
  }
  if (worst < 0) return "no free node";
  return "largest " + fmt("%.3g", std::sqrt(largest)) + " N at node " + std::to_string(worst) + ", X = (" +
         fmt("%.4g", test_.mesh.X(0, worst)) + ", " + fmt("%.4g", test_.mesh.X(1, worst)) + ") mm";
}

std::string Simulation::describe_element_failure() const {
  if (assembled_.status == ElementStatus::inverted)
    return "element " + std::to_string(assembled_.element) + " inverted (det F = " + fmt("%.3g", assembled_.min_detF) +
           ")";
  return "the law returned a non-finite value in element " + std::to_string(assembled_.element);
}

// Why an element may have failed: the law's strong ellipticity at its quadrature points in the state
// of the last assembly (after a failed step: the last converged state). Empty when every point is
// strongly elliptic there.
std::string Simulation::ellipticity_note(int element) const {
  if (element < 0 || element >= test_.mesh.elements()) return {};
  const ElementGeometry g = element_geometry(test_.mesh, element);
  const ElementVector ue = element_displacements(test_.mesh, element, u_);
  const Mat2 Q = material_axes(test_.material_angle);
  LawInput in;
  in.Q = Q;
  in.region = g.region;
  LawOutput out;
  Ellipticity worst{1e300, 0};
  Mat2 E_worst = Mat2::Zero();
  for (int q = 0; q < g.points; ++q) {
    in.F = deformation_gradient(g, q, ue);
    if (!(in.F.determinant() > 0)) return {};
    law_.evaluate(in, LawRequest{}, out);
    if (!out.A.allFinite()) return {};
    const Ellipticity e = strong_ellipticity(out.A);
    if (e.min_eigenvalue < worst.min_eigenvalue)
      worst = e, E_worst = Q.transpose() * 0.5 * (in.F.transpose() * in.F - Mat2::Identity()) * Q;
  }
  if (!(worst.min_eigenvalue < 0)) return {};
  return "; in the last converged state the law is not strongly elliptic in element " + std::to_string(element) +
         " (smallest acoustic eigenvalue " + fmt("%.3g", worst.min_eigenvalue) + " N/mm, direction " +
         fmt("%.0f", worst.angle_deg) + "°, at E11 " + fmt("%.3f", E_worst(0, 0)) + ", E22 " +
         fmt("%.3f", E_worst(1, 1)) + ", E12 " + fmt("%.3f", E_worst(0, 1)) +
         " in the material axes): the membrane localises there";
}

// One (sub)step from the converged state at `from` to `to` (docs/theory.md §4). On entry assembled_ holds a tangent
// at or next to the converged state (that of the last Newton iterate: the converged state itself is
// evaluated for its residual only), and the factorization is of it or of a nearby state; the
// predictor extrapolates along it.
bool Simulation::newton(const Load& from, const Load& to, StepResult& step, Failure& fail) {
  step.residuals.clear();
  const Eigen::VectorXd z0 = z_;
  Eigen::VectorXd rhs = (to.d - from.d) * assembled_.g_grip + (to.c - from.c) * assembled_.g_guide;
  if (dofs_.master >= 0) rhs(dofs_.master) -= 0.5 * (to.F - from.F);
  if (to.t != from.t) {
    rhs += assembled_.K_fs * (detail::series_displacements(dofs_, to.t) - detail::series_displacements(dofs_, from.t));
    for (size_t k = 0; k < dofs_.anchor.size(); ++k)  // tied conditions: ∂R/∂anchor = −t
      if (dofs_.anchor[k] >= 0) {
        const int i = static_cast<int>(k);
        rhs(dofs_.eq[k]) -= dofs_.tie[k] * (detail::tie_anchor(dofs_, i, to) - detail::tie_anchor(dofs_, i, from));
      }
  }
  Eigen::MatrixXd sol;
  Failure ignored;  // without a tangent predictor, Newton starts from z0 and reports its own failure
  if (!linear_solve(rhs, sol, ignored, true)) sol.setZero(rhs.size(), 1);
  const Eigen::VectorXd dz_t = -sol;  // tangent predictor: dz/dτ at z0, τ = 1 at `to`
  Eigen::VectorXd z = z0 + dz_t;
  // When the load keeps its direction, the converged states before (at τ_j < 0) with their tangents
  // fix a Hermite polynomial through them and (z0, dz_t): use it at τ = 1.
  const Eigen::Vector4d e(to.d - from.d, to.F - from.F, to.c - from.c, to.t - from.t);
  const double L = e.norm();
  std::vector<double> tau;  // of the history entries that lie behind `from` on the same line
  for (auto it = history_.rbegin(); it != history_.rend() && L > 0; ++it) {
    const Eigen::Vector4d p(it->load.d - from.d, it->load.F - from.F, it->load.c - from.c, it->load.t - from.t);
    if (!(p.norm() > 0) || (p / p.norm() + e / L).norm() > 1e-9) break;
    tau.push_back(-p.norm() / L);
  }
  const bool along = !tau.empty();
  if (along) {
    // Conditions: values at τ = 0, τ_j and slopes at 0 (dz_t) and at τ_j (L · dz/ds) where known; with
    // M the confluent Vandermonde matrix of these conditions, p(1) = Σ_r w_r data_r, w = M⁻ᵀ (1, …, 1).
    // Two states before (quintic) take the benchmark strip from 1.6 to 1.06 Newton iterations per step.
    struct Row {
      double t;
      bool slope;
      const Eigen::VectorXd* v;
    };
    std::vector<Row> rows{{0, false, &z0}, {0, true, &dz_t}};
    std::vector<Eigen::VectorXd> slopes;
    slopes.reserve(tau.size());
    for (size_t j = 0; j < tau.size(); ++j) {
      const State& h = history_[history_.size() - 1 - j];
      rows.push_back({tau[j], false, &h.z});
      if (h.dz_ds.size() == z0.size()) {
        slopes.push_back(L * h.dz_ds);
        rows.push_back({tau[j], true, &slopes.back()});
      }
    }
    const int n = static_cast<int>(rows.size());
    Eigen::MatrixXd Mt(n, n);  // Mᵀ
    for (int r = 0; r < n; ++r)
      for (int k = 0; k < n; ++k) {
        const double t = rows[r].t;
        Mt(k, r) = rows[r].slope ? (k == 0 ? 0.0 : k * std::pow(t, k - 1)) : std::pow(t, k);
      }
    const Eigen::VectorXd w = Mt.fullPivLu().solve(Eigen::VectorXd::Ones(n));
    z = w(0) * z0;
    for (int r = 1; r < n; ++r) z += w(r) * *rows[r].v;
  }
  bool ok = z.allFinite() && evaluate(z, to);
  if (!ok && along) ok = evaluate(z = z0 + dz_t, to);
  if (!ok) {
    z = z0;  // the predictor overshoots: start from the last state instead
    if (!evaluate(z, to)) {
      fail = {true, describe_element_failure() + " at the start of the increment"};
      fail.element = assembled_.element;
      return false;
    }
  }
  tangent_next_ = L > 0 ? Eigen::VectorXd(dz_t / L) : Eigen::VectorXd();
  return iterate(std::move(z), to, step, fail, options_.max_iterations);
}

// Newton's iterations at `to` from z, the state of the last evaluation (assembled_); z_ = the
// converged state.
// With `chord`, an iteration after the first keeps the last tangent and its factorization while the
// iteration before cut the residual by kChordContraction or more (a warm start's steps). On the
// load path (Newton's method) each iteration assembles and factorizes the tangent: there the chord
// steps saved 8 % of a 24 874-dof rig test's time (47 factorizations instead of 62, but 91 iterations
// instead of 61).
bool Simulation::iterate(Eigen::VectorXd z, const Load& to, StepResult& step, Failure& fail, int max_iterations,
                         bool chord) {
  Eigen::VectorXd R = free_residual(to);
  double r = R.norm(), r_before = INFINITY;  // ‖R‖ before the last iteration
  for (int it = 0;; ++it) {
    const double ref = reference_force(to);
    if (options_.keep_residuals) step.residuals.push_back(r);
    if (reporter_.log)
      reporter_.info("  iteration " + std::to_string(it) + ": |R| = " + fmt("%.3e", r) + " (relative " +
                     fmt("%.3e", r / ref) + ")");
    if (r <= options_.tolerance * ref) break;
    if (it == max_iterations) {
      fail.why = "residual " + fmt("%.3g", r / ref) + " (relative) after " + std::to_string(it) +
                 " Newton iterations, tolerance " + fmt("%.3g", options_.tolerance) + " (" +
                 describe_largest_residual(R) + ")";
      return false;
    }
    ++step.iterations;
    // The line search evaluates residuals only; the tangent at z is assembled when it is needed.
    const bool keep_tangent = chord && it > 0 && r <= kChordContraction * r_before;
    r_before = r;
    if (!tangent_fresh_ && !keep_tangent && !evaluate(z, to)) {
      fail.why = "the accepted state can no longer be evaluated: " + describe_element_failure();
      fail.element = assembled_.element;
      return false;
    }
    Eigen::MatrixXd dzm;
    if (!linear_solve(R, dzm, fail)) return false;
    const Eigen::VectorXd dz = -dzm;
    // Backtracking on ‖R‖ (Armijo): halve α until the residual drops; an inverted trial state counts
    // as no decrease.
    double alpha = 1;
    bool accepted = false;
    for (int ls = 0; ls < (options_.line_search ? 12 : 1); ++ls, alpha *= 0.5) {
      const Eigen::VectorXd zt = z + alpha * dz;
      if (!evaluate(zt, to, false)) continue;
      const Eigen::VectorXd Rt = free_residual(to);
      const double rt = Rt.norm();
      if (!options_.line_search || rt <= (1 - 1e-4 * alpha) * r || rt <= options_.tolerance * reference_force(to)) {
        z = zt, R = Rt, r = rt, accepted = true;
        break;
      }
    }
    if (!accepted) {
      if (assembled_.status != ElementStatus::ok) {  // Newton wandered off (e.g. past a limit point)
        fail.why = "no admissible Newton update: " + describe_element_failure() + " in every line-search trial";
        fail.element = assembled_.element;
      } else {
        fail.why = "the line search found no decrease of the residual (|R| = " + fmt("%.3g", r) + ", " +
                   describe_largest_residual(R) + ")";
      }
      return false;
    }
  }
  // A force-controlled grip that carries a tensile force must have moved outward: Newton can also
  // converge to a compressed equilibrium when the law has none in tension (e.g. a negative initial
  // stiffness, or a load past the law's maximum force). Such a state is not usable.
  if (dofs_.master >= 0 && to.F > 0 && !(z(dofs_.master) > 0)) {
    fail = {true, "converged only to a compressed state: grip displacement " + fmt("%.3g", z(dofs_.master)) +
                      " mm under a tensile force of " + fmt("%.3g", to.F) + " N (no tensile equilibrium of the law)"};
    return false;
  }
  z_ = z;
  peak_reaction_ = std::max(peak_reaction_, reaction_norm(to));
  return true;
}

// The rig's first stage (docs/theory.md §6): the guide moves to its setting with the grip at rest, in
// guide_setting_steps increments (each with its own cutbacks); `where` names the failed increment.
bool Simulation::set_transverse_dimension(Failure& fail, std::string& where, std::vector<StepResult>& states) {
  const int n = test_.guide_setting_steps;
  for (int i = 1; i <= n; ++i) {
    StepResult scratch;
    Load to;
    to.c = test_.guide[0] * i / n;
    if (reporter_.log)
      reporter_.info("setting the transverse dimension: increment " + std::to_string(i) + "/" + std::to_string(n));
    if (!solve_step(to, scratch, fail)) {
      where = "setting the transverse dimension (increment " + std::to_string(i) + " of " + std::to_string(n) +
              ", guide " + fmt("%.6g", to.c) + " mm) failed after " + std::to_string(scratch.cutbacks) + " cutbacks";
      return false;
    }
    scratch.load = 0;  // the grip at rest
    record(load_, scratch);
    states.push_back(std::move(scratch));
  }
  return true;
}

// SolveOptions::warm_start's state for one of its steps: its u, moved by du/dc · Δc where it has them.
Eigen::VectorXd Simulation::warm_state(const StepResult& previous) const {
  Eigen::VectorXd z = unknowns(dofs_, previous.u);
  if (previous.du_dc.size() > 0) z += unknowns(dofs_, previous.du_dc * options_.warm_start_dc);
  return z;
}

// Newton at `to` straight from z_start (SolveOptions::warm_start). False when it fails, with the last
// converged state evaluated again: the caller then takes the load path from there.
bool Simulation::warm_step(const Load& to, const Eigen::VectorXd& z_start, StepResult& step) {
  if (options_.cancelled && options_.cancelled()) return false;  // the load path says so
  const Eigen::VectorXd z_keep = z_;
  Failure fail;
  StepResult trial;
  if (z_start.allFinite() && evaluate(z_start, to) && iterate(z_start, to, trial, fail, kWarmIterations, true)) {
    history_.push_back({load_, z_keep, Eigen::VectorXd()});  // its tangent is unknown
    if (history_.size() > kHistory) history_.erase(history_.begin());
    load_ = to;
    step.iterations += trial.iterations;
    step.residuals = std::move(trial.residuals);
    return true;
  }
  z_ = z_keep;
  evaluate(z_, load_);  // converged before: it evaluates
  return false;
}

// One step of the list, halving the increment on failure (up to max_cutbacks halvings).
bool Simulation::solve_step(const Load& target, StepResult& step, Failure& fail) {
  const Load start = load_;
  auto lerp = [&](double s) {
    return Load{start.d + s * (target.d - start.d), start.F + s * (target.F - start.F),
                start.c + s * (target.c - start.c), start.t + s * (target.t - start.t)};
  };
  double s = 0, ds = 1;
  while (s < 1) {
    if (options_.cancelled && options_.cancelled()) {
      fail = Failure{};
      fail.cancelled = true;
      fail.why = "cancelled";
      return false;
    }
    const double s1 = std::min(1.0, s + ds);
    const Load to = s1 == 1.0 ? target : lerp(s1);
    if (reporter_.log) reporter_.info("increment to " + fmt("%.6g", s1) + " of the step");
    const Eigen::VectorXd z_keep = z_;
    fail = Failure{};
    if (newton(load_, to, step, fail)) {
      s = s1;
      history_.push_back({load_, z_keep, tangent_next_});
      if (history_.size() > kHistory) history_.erase(history_.begin());
      load_ = to;
      continue;
    }
    // Back to the converged state, with its tangent for the next predictor.
    z_ = z_keep;
    if (!evaluate(z_, load_)) {
      fail.why += "; the last converged state can no longer be evaluated";
      return false;
    }
    if (step.cutbacks == options_.max_cutbacks) return false;
    ++step.cutbacks;
    ds *= 0.5;
  }
  return true;
}

// K du_f/dc = −∂R_f/∂c at the converged state (z_, load_) (docs/theory.md §7): one multi-RHS solve, refined on
// the last iterate's factorization, or on its own where that is cheaper (LinearSolver::prefers_factorization:
// the response surface's block LU with its 14 columns, where refining took ~2.1 sweeps); that one then
// serves the next increment's predictor exactly.
bool Simulation::step_sensitivities(StepResult& step, Failure& fail) {
  Eigen::MatrixXd dz;
  // Adds ∂f/∂c, and the tangent at z_ unless the last evaluation (at z_) made it.
  bool ok = evaluate(z_, load_, !tangent_fresh_, true);
  Eigen::MatrixXd dR_dc = Eigen::MatrixXd::Zero(dofs_.equations, coefficient_count_);
  for (size_t d = 0; d < dofs_.eq.size(); ++d)
    if (dofs_.eq[d] >= 0) dR_dc.row(dofs_.eq[d]) += assembled_.df_dc.row(d);
  if (ok) ok = linear_solve(dR_dc, dz, fail, !linear_solver_.prefers_factorization(dR_dc.cols()));
  if (!ok) return false;
  dz = -dz;
  step.du_dc.setZero(dofs_.eq.size(), coefficient_count_);
  for (size_t d = 0; d < dofs_.eq.size(); ++d)
    if (dofs_.eq[d] >= 0) step.du_dc.row(d) = dz.row(dofs_.eq[d]);
  step.dforce_dc.setZero(coefficient_count_);
  if (test_.control == GripControl::displacement) {
    for (int d : dofs_.top_y) step.dforce_dc += assembled_.df_dc.row(d).transpose();
    step.dforce_dc += dz.transpose() * assembled_.h_top;
    step.dforce_dc *= force_scale();
  }
  return true;
}

bool Simulation::add_sensitivities(SimulationResult& result) {
  for (size_t k = 0; k < result.steps.size(); ++k) {
    StepResult& step = result.steps[k];
    load_ = load_at(k);
    z_ = unknowns(dofs_, step.u);
    tangent_fresh_ = false;
    Failure fail;
    if (!step_sensitivities(step, fail)) {
      result.termination = SolveTermination::not_converged;
      result.message = "test '" + test_.name + "': step " + std::to_string(k + 1) +
                       ": sensitivities: " + (fail.why.empty() ? "the converged state cannot be evaluated" : fail.why);
      return false;
    }
  }
  return true;
}

// Reactions and sensitivities at a converged step (docs/theory.md §6, §7).
void Simulation::record(const Load& L, StepResult& step) {
  step.u = u_;
  step.edge_displacement = dofs_.master >= 0 ? z_(dofs_.master) : L.d;
  // The fabric's pull on what holds it: the internal force, without the ties' own force.
  auto pull = [&](int k) { return assembled_.f(k) - dofs_.tie[k] * (u_(k) - detail::tie_anchor(dofs_, k, L)); };
  double top = 0, side = 0;
  for (int k : dofs_.top_y) top += pull(k);
  for (int k : dofs_.right_x) side += pull(k);
  step.edge_force = force_scale() * top;
  step.side_force = test_.side == SideEdge::guide ? 2 * side : 0.0;
  step.resultants.clear();
  for (const std::vector<int>& nodes : dofs_.resultant_nodes) {
    Vec2 sum = Vec2::Zero();
    for (int n : nodes) sum += Vec2(pull(2 * n), pull(2 * n + 1));
    step.resultants.push_back(sum);
  }
  if (!test_.has_conditions()) {
    step.force_per_width = step.edge_force / (2 * test_.mesh.X.row(0).maxCoeff());
    return;
  }
  // Any mesh: the force boundary's prescribed displacement, and the force per unit initial width.
  const double width = test_.mesh.X.row(0).maxCoeff() - test_.mesh.X.row(0).minCoeff();
  step.edge_displacement = dofs_.top_y.empty() ? 0.0 : u_(dofs_.top_y.front());
  step.force_per_width = step.edge_force / width;
}

SimulationResult Simulation::run() {
  SimulationResult result;
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = test_.loads.size();
  if (reporter_.log) reporter_.info("linear solver: " + linear_solver_.description());
  z_.setZero(dofs_.equations);
  Failure fail;
  const SimulationResult* warm = options_.warm_start;
  // Without sensitivities a nearby law's states start Newton further off than the load path's predictor.
  if (warm &&
      (!warm->usable() || warm->steps.size() != n || warm->steps.front().du_dc.cols() != options_.warm_start_dc.size()))
    warm = nullptr;
  // The reference state's tangent starts the first predictor (a warm start needs none).
  if (!evaluate(z_, load_) || (!warm && !factorize(fail))) {
    result.termination =
        assembled_.status != ElementStatus::ok ? SolveTermination::invalid_state : SolveTermination::not_converged;
    result.message = "test '" + test_.name + "': the reference state cannot be solved: " +
                     (assembled_.status != ElementStatus::ok ? describe_element_failure() : fail.why);
  }
  if (result.usable() && test_.guide_setting_steps > 0) {
    std::string where;
    StepResult set;
    Load to;
    to.c = test_.guide[0];
    if (warm && !warm->setting.empty() && warm_step(to, warm_state(warm->setting.back()), set)) {
      record(load_, set);
      result.setting.push_back(std::move(set));
    } else if (!set_transverse_dimension(fail, where, result.setting)) {
      result.termination = termination(fail);
      result.message = "test '" + test_.name + "': " + where + ": " + fail.why + ellipticity_note(fail.element);
    }
  }
  for (size_t k = 0; k < n && result.usable(); ++k) {
    StepResult step;
    step.load = test_.loads[k];
    if (reporter_.log)
      reporter_.info("step " + std::to_string(k + 1) + "/" + std::to_string(n) + ", load " + fmt("%.6g", step.load));
    bool warm_done = false;
    if (warm) {  // from this run's last state, moved by the warm run's increment to the step: that
      // increment's error is the change over one step of the two runs' difference, far smaller than the
      // difference itself when c moved far (docs/theory.md §7.1)
      const StepResult* before = k > 0 ? &warm->steps[k - 1] : warm->setting.empty() ? nullptr : &warm->setting.back();
      Eigen::VectorXd z_start = z_ + warm_state(warm->steps[k]);
      if (before) z_start -= warm_state(*before);
      warm_done = warm_step(load_at(k), z_start, step);
    }
    if (!warm_done && !solve_step(load_at(k), step, fail)) {
      result.termination = termination(fail);
      result.message = "test '" + test_.name + "': step " + std::to_string(k + 1) + " of " + std::to_string(n) +
                       " (load " + fmt("%.6g", step.load) + ") failed after " + std::to_string(step.cutbacks) +
                       " cutbacks: " + fail.why + ellipticity_note(fail.element);
      break;
    }
    if (options_.sensitivities && !step_sensitivities(step, fail)) {
      result.termination = SolveTermination::not_converged;
      result.message = "test '" + test_.name + "': step " + std::to_string(k + 1) +
                       ": sensitivities: " + (fail.why.empty() ? "the converged state cannot be evaluated" : fail.why);
      break;
    }
    record(load_, step);
    result.steps.push_back(std::move(step));
    const StepResult& s = result.steps.back();
    reporter_.report({"simulate " + test_.name, k + 1, n,
                      "step " + std::to_string(k + 1) + "/" + std::to_string(n) + ", " + std::to_string(s.iterations) +
                          " Newton iterations, " + std::to_string(s.cutbacks) + " cutbacks"});
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result.factorization_seconds = linear_solver_.seconds;
  result.factorizations = linear_solver_.factorizations;
  if (result.usable()) result.message = "test '" + test_.name + "': " + std::to_string(n) + " steps converged";
  return result;
}

}  // namespace

SimulationResult simulate(const TestModel& test, const Law& law, const SolveOptions& options,
                          const Reporter& reporter) {
  options.validate();
  test.validate();
  Simulation sim(test, law, options, reporter);
  return sim.run();
}

bool add_sensitivities(const TestModel& test, const Law& law, SimulationResult& result, const SolveOptions& options) {
  SolveOptions o = options;
  o.sensitivities = true;
  o.validate();
  if (!result.usable() || result.steps.size() != test.loads.size()) return false;
  const Reporter quiet;
  Simulation sim(test, law, o, quiet);
  return sim.add_sensitivities(result);
}

}  // namespace tricot::fem
