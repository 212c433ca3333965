// The active set of a bounded LM run and its cut steps (lm.hpp; docs/theory.md §3.1, §3.2).
#include "lm.hpp"

#include <algorithm>
#include <utility>

namespace tricot::ident::detail {

bool StepManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n_);
  for (size_t i = 0; i < free_.size(); ++i) d(free_[i]) = delta[i];
  const Eigen::Map<const Eigen::VectorXd> x0(x, n_);
  const double t = fraction_ && d.squaredNorm() > 0 ? fraction_(x0, d) : 1.0;
  Eigen::Map<Eigen::VectorXd>(x_plus_delta, n_) = x0 + t * d;
  return true;
}

bool StepManifold::PlusJacobian(const double*, double* jacobian) const {
  const int m = TangentSize();
  std::fill(jacobian, jacobian + n_ * m, 0.0);
  for (int i = 0; i < m; ++i) jacobian[free_[i] * m + i] = 1;
  return true;
}

bool StepManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  for (size_t i = 0; i < free_.size(); ++i) y_minus_x[i] = y[free_[i]] - x[free_[i]];
  return true;
}

bool StepManifold::MinusJacobian(const double*, double* jacobian) const {
  const int m = TangentSize();
  std::fill(jacobian, jacobian + n_ * m, 0.0);
  for (int i = 0; i < m; ++i) jacobian[i * n_ + free_[i]] = 1;
  return true;
}

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
  if (!released.empty())
    reporter.info("identify: released from its bound (f decreases into the box): " + joined(released));
  return !released.empty();
}

}  // namespace tricot::ident::detail
