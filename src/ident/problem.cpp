// Parameters and Jacobians of a least-squares problem (docs/theory.md §3): exact, or finite differences
// with the columns evaluated in parallel (the paper computed them one after the other).
#include "tricot/ident/problem.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "tricot/core/error.hpp"

namespace tricot::ident {

std::string force_scale_test(const std::string& parameter) {
  const std::string suffix = std::string(".") + kForceScale;
  if (parameter.size() <= suffix.size() || !parameter.ends_with(suffix)) return {};
  return parameter.substr(0, parameter.size() - suffix.size());
}

double Parameter::resolved_scale() const { return scale > 0 ? scale : std::abs(start); }

void validate(const std::vector<Parameter>& parameters) {
  if (parameters.empty()) throw InputError(Location{"", 0, "parameters"}, "no parameter to identify");
  std::set<std::string> seen;
  for (const Parameter& p : parameters) {
    const std::string key = "parameters." + p.name;
    auto fail = [&](const std::string& field, const std::string& problem, const std::string& got,
                    const std::string& expected) {
      throw InputError(Location{"", 0, field.empty() ? key : key + "." + field}, problem, got, expected);
    };
    if (p.name.empty()) throw InputError(Location{"", 0, "parameters"}, "a parameter without a name");
    if (!seen.insert(p.name).second) fail("", "listed twice", p.name, "each coefficient once");
    if (!std::isfinite(p.start)) fail("start", "start value must be finite", format_number(p.start), "a number");
    if (!(p.scale >= 0) || !std::isfinite(p.scale)) fail("scale", "out of range", format_number(p.scale), ">= 0");
    if (!(p.lower < p.upper))
      fail("lower", "lower bound not below upper bound", format_number(p.lower), "< " + format_number(p.upper));
    if (p.start < p.lower || p.start > p.upper)
      fail("start", "start value outside the bounds", format_number(p.start),
           "[" + format_number(p.lower) + ", " + format_number(p.upper) + "]");
    if (p.start == 0 && p.scale == 0)
      fail("scale", "a zero start value needs an explicit scale (LM works in J/scale)", "0", "> 0");
  }
}

const char* to_string(JacobianMode m) { return m == JacobianMode::exact ? "exact" : "finite_difference"; }
const char* to_string(Difference d) { return d == Difference::forward ? "forward" : "central"; }

Evaluation evaluate(const Problem& problem, const Eigen::VectorXd& J, bool jacobian, const JacobianOptions& options,
                    const Evaluation* base) {
  if (options.mode == JacobianMode::exact || !jacobian) {
    Evaluation e = problem.evaluate(J, jacobian);
    e.evaluations = std::max(e.evaluations, 1);
    return e;
  }
  // Finite differences: column k from trials at J ± h_k e_k, h_k = step · scale_k.
  Evaluation e = base ? *base : problem.evaluate(J, false);
  if (!base) e.evaluations = 1;
  else e.evaluations = 0;
  if (!e.ok) return e;
  const auto& params = problem.parameters();
  const int n = static_cast<int>(J.size());
  const bool central = options.difference == Difference::central;
  // Trials: (k, +) for every column, and (k, −) for central differences.
  const int trials = central ? 2 * n : n;
  std::vector<Evaluation> trial(trials);
  std::vector<double> h(n);
  for (int k = 0; k < n; ++k) h[k] = options.step * params[k].resolved_scale();
  auto run = [&](int i, double sign) {
    const int k = i % n;
    Eigen::VectorXd Jt = J;
    Jt(k) += sign * h[k];
    return problem.evaluate(Jt, false);
  };
  const int threads = thread_team(options.threads);
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (int i = 0; i < trials; ++i) trial[i] = run(i, i < n ? 1.0 : -1.0);
  e.evaluations += trials;
  e.jacobian.resize(e.r.size(), n);
  for (int k = 0; k < n; ++k) {
    const Evaluation& plus = trial[k];
    if (central) {
      const Evaluation& minus = trial[n + k];
      if (plus.ok && minus.ok) {
        e.jacobian.col(k) = (plus.r - minus.r) / (2 * h[k]);
        continue;
      }
      if (plus.ok) e.jacobian.col(k) = (plus.r - e.r) / h[k];
      else if (minus.ok) e.jacobian.col(k) = (e.r - minus.r) / h[k];
      else {
        e.ok = false;
        e.message = "finite differences for " + params[k].name + ": " + plus.message;
        return e;
      }
      continue;
    }
    if (plus.ok) {
      e.jacobian.col(k) = (plus.r - e.r) / h[k];
      continue;
    }
    const Evaluation minus = run(k, -1.0);  // a forward trial failed: try backward
    ++e.evaluations;
    if (!minus.ok) {
      e.ok = false;
      e.message = "finite differences for " + params[k].name + ": " + plus.message;
      return e;
    }
    e.jacobian.col(k) = (e.r - minus.r) / h[k];
  }
  return e;
}

int thread_team(int threads) { return threads > 0 ? std::min(threads, omp_get_num_procs()) : omp_get_max_threads(); }

}  // namespace tricot::ident
