// Quasi-static solution of a test model (THEORY §4–§7): load stepping with cutback, Newton–Raphson with
// the consistent tangent and a backtracking line search, reactions, and exact sensitivities.
#include "tricot/fem/solver.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "assembly.hpp"
#include "linear_solver.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {

void SolveOptions::validate() const {
  auto bad = [](const char* key, const std::string& got, const std::string& expected) {
    throw InputError(Location{"", 0, key}, "out of range", got, expected);
  };
  if (!(tolerance > 0) || !std::isfinite(tolerance)) bad("solver.tolerance", std::to_string(tolerance), "> 0");
  if (max_iterations < 1 || max_iterations > 200) bad("solver.max_iterations", std::to_string(max_iterations), "1 to 200");
  if (max_cutbacks < 0 || max_cutbacks > 30) bad("solver.max_cutbacks", std::to_string(max_cutbacks), "0 to 30");
}

const char* to_string(SolveTermination t) {
  switch (t) {
    case SolveTermination::converged: return "converged";
    case SolveTermination::not_converged: return "not_converged";
    case SolveTermination::invalid_state: return "invalid_state";
  }
  return "?";
}

namespace {

using detail::Assembled;
using detail::Load;

constexpr int kMaxRefinements = 8;
constexpr double kRefinedResidual = 1e-13;  // ‖b − K x‖/‖b‖ of a refined solve: near round-off

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
};

class Simulation {
 public:
  Simulation(const TestModel& test, const Law& law, const SolveOptions& options, const Reporter& reporter)
      : test_(test), opt_(options), rep_(reporter), dofs_(detail::make_dof_map(test)),
        asm_(test, dofs_, law), lin_(asm_.pattern()), nc_(static_cast<int>(law.coefficients().size())) {}

  SimulationResult run();

 private:
  Load load_at(size_t k) const;
  bool evaluate(const Eigen::VectorXd& z, const Load& L, bool tangent = true, bool sensitivities = false);
  bool solve_current(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) const;
  Eigen::VectorXd free_residual(const Load& L) const;
  double reaction_norm(const Load& L) const;
  bool factorize(Failure& fail);
  bool newton(const Load& from, const Load& to, StepResult& step, Failure& fail);
  bool solve_step(size_t k, StepResult& step, Failure& fail);
  void record(const Load& L, StepResult& step);
  std::string describe_element_failure() const;

  const TestModel& test_;
  const SolveOptions& opt_;
  const Reporter& rep_;
  detail::DofMap dofs_;
  detail::Assembler asm_;
  detail::LinearSolver lin_;
  int nc_;
  Assembled a_;           // the last assembly
  bool factor_current_ = false;  // the factorization is of a_.K (else of an earlier, nearby state)
  Eigen::VectorXd u_;     // node displacements of the last assembly
  Eigen::VectorXd z_;     // converged unknowns
  Load load_;             // converged load
  Eigen::VectorXd z_prev_;  // the converged state before, for the predictor's curvature
  Load load_prev_;
  bool has_prev_ = false;
  Eigen::VectorXd tangent_prev_;  // the predictor's dz from z_prev to z (empty: none)
  Eigen::VectorXd tangent_next_;
};

Load Simulation::load_at(size_t k) const {
  Load L;
  const double v = test_.loads[k];
  (test_.control == GripControl::displacement ? L.d : L.F) = v;
  if (test_.side == SideEdge::guide)
    L.c = test_.guide.size() == 1 ? test_.guide[0] * v / test_.loads.back() : test_.guide[k];
  return L;
}

bool Simulation::evaluate(const Eigen::VectorXd& z, const Load& L, bool tangent, bool sensitivities) {
  detail::expand(dofs_, z, L, u_);
  LawRequest req;
  req.tangent = tangent;
  req.sensitivities = sensitivities;
  if (tangent) factor_current_ = false;
  return asm_.assemble(u_, req, a_);
}

// K(a_) x = b. When the factorization is of an earlier Newton iterate (Newton converged without
// refactorizing), iterative refinement against the current K makes the solve exact at the cost of
// products with K: the sensitivities (THEORY §7) and the predictor then use the converged tangent
// without a factorization of their own. False when the refinement does not contract.
bool Simulation::solve_current(const Eigen::MatrixXd& b, Eigen::MatrixXd& x) const {
  x = lin_.solve(b);
  if (factor_current_) return x.allFinite();
  const double nb = b.norm();
  if (nb == 0) return true;
  double prev = INFINITY;
  for (int it = 0; it < kMaxRefinements; ++it) {
    const Eigen::MatrixXd rho = b - a_.K * x;
    const double rel = rho.norm() / nb;
    if (!(rel < 0.5 * prev)) return false;  // not contracting (or not finite)
    if (rel <= kRefinedResidual) return true;
    prev = rel;
    x += lin_.solve(rho);
  }
  return false;
}

// R_f = Σ f_int over each equation's dofs − the quarter's share F/2 of the grip force (THEORY §6).
Eigen::VectorXd Simulation::free_residual(const Load& L) const {
  Eigen::VectorXd R = Eigen::VectorXd::Zero(dofs_.equations);
  for (size_t k = 0; k < dofs_.eq.size(); ++k)
    if (dofs_.eq[k] >= 0) R(dofs_.eq[k]) += a_.f(k);
  if (dofs_.master >= 0) R(dofs_.master) -= 0.5 * L.F;
  return R;
}

double Simulation::reaction_norm(const Load& L) const {
  double s = dofs_.master >= 0 ? 0.25 * L.F * L.F : 0.0;
  for (size_t k = 0; k < dofs_.eq.size(); ++k)
    if (dofs_.eq[k] < 0) s += a_.f(k) * a_.f(k);
  return std::sqrt(s);
}

bool Simulation::factorize(Failure& fail) {
  factor_current_ = lin_.factorize(a_.K, a_.symmetric);
  if (factor_current_) return true;
  fail.why = "the tangent is singular";
  return false;
}

std::string Simulation::describe_element_failure() const {
  if (a_.status == ElementStatus::inverted)
    return "element " + std::to_string(a_.element) + " inverted (det F = " + fmt("%.3g", a_.min_detF) + ")";
  return "the law returned a non-finite value in element " + std::to_string(a_.element);
}

// One (sub)step from the converged state at `from` to `to` (THEORY §4). On entry a_ and the
// factorization hold the tangent at the converged state; the predictor extrapolates along it.
bool Simulation::newton(const Load& from, const Load& to, StepResult& step, Failure& fail) {
  step.residuals.clear();
  const Eigen::VectorXd z0 = z_;
  Eigen::VectorXd rhs = (to.d - from.d) * a_.g_grip + (to.c - from.c) * a_.g_guide;
  if (dofs_.master >= 0) rhs(dofs_.master) -= 0.5 * (to.F - from.F);
  Eigen::MatrixXd sol;
  if (!solve_current(rhs, sol)) sol = lin_.solve(rhs);  // a rougher predictor still starts Newton
  const Eigen::VectorXd dz_t = -sol;  // tangent predictor: dz/dτ at z0, τ = 1 at `to`
  Eigen::VectorXd z = z0 + dz_t;
  // When the load keeps its direction, the converged state before (at τ = −h) and its tangent fix a
  // cubic (Hermite) or, without that tangent, a parabola through z_prev and z0; use it at τ = 1.
  bool along = false;
  double h = 0;
  if (has_prev_) {
    const Eigen::Vector3d e(to.d - from.d, to.F - from.F, to.c - from.c),
        p(load_prev_.d - from.d, load_prev_.F - from.F, load_prev_.c - from.c);
    h = p.norm() / e.norm();
    along = h > 0 && (p / p.norm() + e / e.norm()).norm() < 1e-9;
  }
  if (along) {
    const Eigen::VectorXd D1 = z_prev_ - z0 + h * dz_t;  // = a h² − b h³
    if (tangent_prev_.size() == z0.size()) {
      const Eigen::VectorXd D2 = tangent_prev_ / h - dz_t;  // = −2 a h + 3 b h²
      z += (3 / (h * h) + 2 / (h * h * h)) * D1 + (1 / h + 1 / (h * h)) * D2;
    } else {
      z += D1 / (h * h);
    }
  }
  bool ok = z.allFinite() && evaluate(z, to);
  if (!ok && along) ok = evaluate(z = z0 + dz_t, to);
  if (!ok) {
    z = z0;  // the predictor overshoots: start from the last state instead
    if (!evaluate(z, to)) {
      fail = {true, describe_element_failure() + " at the start of the increment"};
      return false;
    }
  }
  tangent_next_ = dz_t;
  Eigen::VectorXd R = free_residual(to);
  double r = R.norm();
  for (int it = 0;; ++it) {
    const double ref = std::max(reaction_norm(to), 1e-12);
    if (opt_.keep_residuals) step.residuals.push_back(r);
    if (rep_.log)
      rep_.info("  iteration " + std::to_string(it) + ": |R| = " + fmt("%.3e", r) + " (relative " +
                fmt("%.3e", r / ref) + ")");
    if (r <= opt_.tolerance * ref) break;
    if (it == opt_.max_iterations) {
      fail.why = "residual " + fmt("%.3g", r / ref) + " (relative) after " + std::to_string(it) +
                 " Newton iterations, tolerance " + fmt("%.3g", opt_.tolerance);
      return false;
    }
    ++step.iterations;
    if (!factorize(fail)) return false;
    const Eigen::VectorXd dz = -lin_.solve(R);
    if (!dz.allFinite()) {
      fail.why = "the tangent is singular";
      return false;
    }
    // Backtracking on ‖R‖ (Armijo): halve α until the residual drops; an inverted trial state counts
    // as no decrease.
    double alpha = 1;
    bool accepted = false;
    for (int ls = 0; ls < (opt_.line_search ? 12 : 1); ++ls, alpha *= 0.5) {
      const Eigen::VectorXd zt = z + alpha * dz;
      if (!evaluate(zt, to)) continue;
      const Eigen::VectorXd Rt = free_residual(to);
      const double rt = Rt.norm();
      if (!opt_.line_search || rt <= (1 - 1e-4 * alpha) * r || rt <= opt_.tolerance * std::max(reaction_norm(to), 1e-12)) {
        z = zt, R = Rt, r = rt, accepted = true;
        break;
      }
    }
    if (!accepted) {
      if (a_.status != ElementStatus::ok) {  // Newton wandered off (e.g. past a limit point)
        fail.why = "no admissible Newton update: " + describe_element_failure() + " in every line-search trial";
      } else {
        fail.why = "the line search found no decrease of the residual (|R| = " + fmt("%.3g", r) + ")";
      }
      return false;
    }
  }
  z_ = z;
  return true;
}

// One step of the list, halving the increment on failure (up to max_cutbacks halvings).
bool Simulation::solve_step(size_t k, StepResult& step, Failure& fail) {
  const Load start = load_, target = load_at(k);
  auto lerp = [&](double s) {
    return Load{start.d + s * (target.d - start.d), start.F + s * (target.F - start.F),
                start.c + s * (target.c - start.c)};
  };
  double s = 0, ds = 1;
  while (s < 1) {
    const double s1 = std::min(1.0, s + ds);
    const Load to = s1 == 1.0 ? target : lerp(s1);
    if (rep_.log)
      rep_.info("step " + std::to_string(k + 1) + ": increment to " + fmt("%.6g", s1) + " of the step");
    const Eigen::VectorXd z_keep = z_;
    fail = Failure{};
    if (newton(load_, to, step, fail)) {
      s = s1;
      z_prev_ = z_keep, load_prev_ = load_, has_prev_ = true, tangent_prev_ = tangent_next_;
      load_ = to;
      continue;
    }
    // Back to the converged state, with its tangent for the next predictor.
    z_ = z_keep;
    Failure again;
    if (!evaluate(z_, load_) || !factorize(again)) {
      fail.why += "; the last converged state can no longer be evaluated";
      return false;
    }
    if (step.cutbacks == opt_.max_cutbacks) return false;
    ++step.cutbacks;
    ds *= 0.5;
  }
  return true;
}

// Reactions and sensitivities at a converged step (THEORY §6, §7).
void Simulation::record(const Load& L, StepResult& step) {
  step.u = u_;
  step.edge_displacement = dofs_.master >= 0 ? z_(dofs_.master) : L.d;
  double top = 0, side = 0;
  for (int k : dofs_.top_y) top += a_.f(k);
  for (int k : dofs_.right_x) side += a_.f(k);
  step.edge_force = 2 * top;
  step.force_per_width = step.edge_force / (2 * test_.mesh.X.row(0).maxCoeff());
  step.side_force = test_.side == SideEdge::guide ? 2 * side : 0.0;
}

SimulationResult Simulation::run() {
  SimulationResult result;
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = test_.loads.size();
  z_.setZero(dofs_.equations);
  Failure fail;
  // The reference state's tangent starts the first predictor.
  if (!evaluate(z_, load_) || !factorize(fail)) {
    result.termination = a_.status != ElementStatus::ok ? SolveTermination::invalid_state
                                                        : SolveTermination::not_converged;
    result.message = "test '" + test_.name + "': the reference state cannot be solved: " +
                     (a_.status != ElementStatus::ok ? describe_element_failure() : fail.why);
  }
  for (size_t k = 0; k < n && result.usable(); ++k) {
    StepResult step;
    step.load = test_.loads[k];
    if (rep_.log) rep_.info("step " + std::to_string(k + 1) + "/" + std::to_string(n) + ", load " + fmt("%.6g", step.load));
    if (!solve_step(k, step, fail)) {
      result.termination = fail.invalid ? SolveTermination::invalid_state : SolveTermination::not_converged;
      result.message = "test '" + test_.name + "': step " + std::to_string(k + 1) + " of " + std::to_string(n) +
                       " (load " + fmt("%.6g", step.load) + ") failed after " + std::to_string(step.cutbacks) +
                       " cutbacks: " + fail.why;
      break;
    }
    if (opt_.sensitivities) {
      // K du_f/dc = −∂R_f/∂c with the converged tangent: one multi-RHS solve, refined against K when
      // Newton converged without refactorizing (a factorization only if that does not contract).
      Eigen::MatrixXd dz;
      bool ok = evaluate(z_, load_, false, true);  // adds ∂f/∂c; the tangent at z_ is already there
      Eigen::MatrixXd dR_dc = Eigen::MatrixXd::Zero(dofs_.equations, nc_);
      for (size_t d = 0; d < dofs_.eq.size(); ++d)
        if (dofs_.eq[d] >= 0) dR_dc.row(dofs_.eq[d]) += a_.df_dc.row(d);
      if (ok && !solve_current(dR_dc, dz)) {
        ok = factorize(fail);
        if (ok) dz = lin_.solve(dR_dc);
      }
      if (!ok || !dz.allFinite()) {
        result.termination = SolveTermination::not_converged;
        result.message = "test '" + test_.name + "': step " + std::to_string(k + 1) + ": sensitivities: " +
                         (fail.why.empty() ? "the converged state cannot be evaluated" : fail.why);
        break;
      }
      dz = -dz;
      step.du_dc.setZero(dofs_.eq.size(), nc_);
      for (size_t d = 0; d < dofs_.eq.size(); ++d)
        if (dofs_.eq[d] >= 0) step.du_dc.row(d) = dz.row(dofs_.eq[d]);
      step.dforce_dc.setZero(nc_);
      if (test_.control == GripControl::displacement) {
        for (int d : dofs_.top_y) step.dforce_dc += a_.df_dc.row(d).transpose();
        step.dforce_dc += dz.transpose() * a_.h_top;
        step.dforce_dc *= 2;
      }
    }
    record(load_, step);
    result.steps.push_back(std::move(step));
    const StepResult& s = result.steps.back();
    rep_.report({"simulate " + test_.name, k + 1, n,
                 "step " + std::to_string(k + 1) + "/" + std::to_string(n) + ", " + std::to_string(s.iterations) +
                     " Newton iterations, " + std::to_string(s.cutbacks) + " cutbacks"});
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result.factorization_seconds = lin_.seconds;
  result.factorizations = lin_.factorizations;
  if (result.usable())
    result.message = "test '" + test_.name + "': " + std::to_string(n) + " steps converged";
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

}  // namespace tricot::fem
