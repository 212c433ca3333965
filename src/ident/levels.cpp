// Identification by mesh levels (docs/theory.md §3.3): the coarsest level by LM, each finer one by
// the coarse model corrected to it (space mapping).
#include <algorithm>
#include <chrono>

#include "tricot/core/error.hpp"
#include "tricot/core/format.hpp"
#include "tricot/ident/identify.hpp"

namespace tricot::ident {

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
    reporter.report(
        {"identify", static_cast<std::size_t>(r.iterations), 0,
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
      throw InputError(where, "levels that identify different parameters",
                       "the same names, scales and bounds on every level", "different ones");
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
