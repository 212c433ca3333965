// Analytic least-squares problems for the identification tests: a model y(J) with its exact
// derivative, compared with data through the same eq. (1) scaling as the FE objective.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cmath>
#include <functional>
#include <vector>

#include "tricot/ident/groups.hpp"
#include "tricot/ident/problem.hpp"

namespace tricot::ident::test {

class AnalyticProblem : public Problem {
 public:
  using Model = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;
  using Derivative = std::function<Eigen::MatrixXd(const Eigen::VectorXd&)>;

  /// One group of data y_exp (σ = 0: scaled by its RMS).
  AnalyticProblem(std::vector<Parameter> parameters, Model model, Derivative derivative, const Eigen::VectorXd& y_exp,
                  double sigma = 0)
      : parameters_(std::move(parameters)), model_(std::move(model)), derivative_(std::move(derivative)) {
    data_.add("curve", GroupKind::edge_force, -1, y_exp, 1, sigma);
  }

  const std::vector<Parameter>& parameters() const override { return parameters_; }
  int residuals() const override { return data_.size(); }
  Eigen::VectorXd residual_variance() const override { return data_.sigma_variance(); }
  Evaluation evaluate(const Eigen::VectorXd& J, bool jacobian) const override {
    ++calls;
    Evaluation e;
    e.evaluations = 1;
    if (fails && fails(J)) {
      e.message = "the model fails here";
      return e;
    }
    e.y = model_(J);
    e.r = data_.residuals(e.y);
    if (jacobian) {
      e.jacobian = derivative_(J);
      data_.scale_rows(e.jacobian);
    }
    e.ok = true;
    return e;
  }

  /// A region of J where the model "does not converge" (evaluate returns ok = false).
  std::function<bool(const Eigen::VectorXd&)> fails;
  /// Problem::lower_bound (0 when empty).
  std::function<double(const Eigen::VectorXd&)> bound;
  double lower_bound(const Eigen::VectorXd& J) const override { return bound ? bound(J) : 0.0; }
  bool has_lower_bound() const override { return static_cast<bool>(bound); }
  mutable std::atomic<int> calls{0};
  ScaledResiduals data_;

 private:
  std::vector<Parameter> parameters_;
  Model model_;
  Derivative derivative_;
};

/// y(t) = A (1 − exp(−t/τ)) + B t at t = 0.1, 0.2, …, 5: J = (A, τ, B).
inline Eigen::VectorXd curve_times() { return Eigen::VectorXd::LinSpaced(50, 0.1, 5.0); }
inline Eigen::VectorXd curve(const Eigen::VectorXd& J) {
  const Eigen::VectorXd t = curve_times();
  return (J(0) * (1 - (-t.array() / J(1)).exp()) + J(2) * t.array()).matrix();
}
inline Eigen::MatrixXd curve_derivative(const Eigen::VectorXd& J) {
  const Eigen::ArrayXd t = curve_times().array(), e = (-t / J(1)).exp();
  Eigen::MatrixXd D(t.size(), 3);
  D.col(0) = (1 - e).matrix();
  D.col(1) = (-J(0) * e * t / (J(1) * J(1))).matrix();
  D.col(2) = t.matrix();
  return D;
}

inline std::vector<Parameter> curve_parameters(const Eigen::Vector3d& start) {
  return {Parameter{"A", start(0)}, Parameter{"tau", start(1)}, Parameter{"B", start(2)}};
}

inline AnalyticProblem curve_fit(const Eigen::Vector3d& truth, const Eigen::Vector3d& start) {
  return AnalyticProblem(curve_parameters(start), curve, curve_derivative, curve(truth));
}

}  // namespace tricot::ident::test
