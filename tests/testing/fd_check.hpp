// The one shared finite-difference checker: every hand-derived tangent, Jacobian or
// sensitivity in tricot is compared with central differences through these functions.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace tricot::test {

/// Central-difference Jacobian of f: Rⁿ → Rᵐ at x, step h·max(1, |x_j|) per column.
template <class Fn>
Eigen::MatrixXd fd_jacobian(Fn&& f, const Eigen::VectorXd& x, double h = 1e-6) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const double hj = h * std::max(1.0, std::abs(x(j)));
    Eigen::VectorXd xp = x, xm = x;
    xp(j) += hj;
    xm(j) -= hj;
    J.col(j) = (f(xp) - f(xm)) / (2 * hj);
  }
  return J;
}

/// Largest entry-wise difference between J and its central-difference estimate, relative to the
/// largest entry of the estimate (so that structurally tiny entries do not dominate).
template <class Fn>
double jacobian_error(Fn&& f, const Eigen::VectorXd& x, const Eigen::MatrixXd& J, double h = 1e-6) {
  const Eigen::MatrixXd Jfd = fd_jacobian(f, x, h);
  const double scale = std::max(Jfd.cwiseAbs().maxCoeff(), 1e-300);
  return (J - Jfd).cwiseAbs().maxCoeff() / scale;
}

/// gtest assertion: EXPECT_TRUE(tricot::test::JacobianMatches(f, x, J, tol)) prints both matrices on failure.
template <class Fn>
::testing::AssertionResult JacobianMatches(Fn&& f, const Eigen::VectorXd& x, const Eigen::MatrixXd& J, double tol,
                                           double h = 1e-6) {
  const Eigen::MatrixXd Jfd = fd_jacobian(f, x, h);
  if (Jfd.rows() != J.rows() || Jfd.cols() != J.cols())
    return ::testing::AssertionFailure() << "shape " << J.rows() << "x" << J.cols() << " vs finite differences "
                                         << Jfd.rows() << "x" << Jfd.cols();
  const double scale = std::max(Jfd.cwiseAbs().maxCoeff(), 1e-300);
  const double err = (J - Jfd).cwiseAbs().maxCoeff() / scale;
  if (err <= tol) return ::testing::AssertionSuccess() << "relative error " << err;
  std::ostringstream o;
  o << "relative error " << err << " > " << tol << "\nanalytic:\n" << J << "\nfinite differences:\n" << Jfd;
  return ::testing::AssertionFailure() << o.str();
}

}  // namespace tricot::test
