// The LM cost function: the whole residual vector of eq. (1) over x = J / scale (lm.hpp).
#include "lm.hpp"

#include <algorithm>

namespace tricot::ident::detail {

bool LmCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Index n = scales_.size();
  const Eigen::Map<const Eigen::VectorXd> x(parameters[0], n);
  const bool want_jacobian = jacobians && jacobians[0];
  if (!want_jacobian) last_trial = x;  // Ceres evaluates each trial point without the Jacobian
  const Evaluation* e = at(x, want_jacobian);
  if (!e) return false;
  Eigen::Map<Eigen::VectorXd>(residuals, e->r.size()) = e->r;
  if (want_jacobian) {
    ++state_.jacobian_evaluations;
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[0], e->r.size(), n) =
        e->jacobian * scales_.asDiagonal();  // ∂r/∂x = ∂r/∂J · scale
  }
  return true;
}

const Evaluation* LmCost::at(const Eigen::VectorXd& x, bool jacobian) const {
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

Eigen::VectorXd LmCost::gradient(const Eigen::VectorXd& x) const {
  const Evaluation* e = at(x, true);
  if (!e) return {};
  return scales_.cwiseProduct(e->jacobian.transpose() * e->r);
}

}  // namespace tricot::ident::detail
