// A small law for the FE engine's tests (not a product law): 2-D compressible neo-Hookean with an
// optional fibre along the course axis and an optional energy saturation that makes it soften.
//   W0 = μ/2 (I1 − 2 − 2 ln J) + λ/2 (ln J)² + κ/2 (a·C·a − 1)²,   a = Q.col(0)
//   W  = W0                        (saturation = ∞)
//   W  = s (1 − exp(−W0/s))        (finite saturation s: the force has a maximum, past which no
//                                   force-controlled equilibrium exists)
// P = ∂W/∂F, A = ∂P/∂F and ∂P/∂(μ, λ, κ) in closed form; each is checked by finite differences in
// element_test.cpp.
#pragma once

#include <cmath>
#include <limits>
#include <memory>

#include <Eigen/LU>

#include "tricot/fem/law.hpp"

namespace tricot::test {

class TestingLaw : public fem::Law {
 public:
  explicit TestingLaw(double mu = 1, double lambda = 2, double kappa = 0,
                      double saturation = std::numeric_limits<double>::infinity())
      : c_(Eigen::Vector3d(mu, lambda, kappa)), s_(saturation) {}

  std::string name() const override { return "testing-neo-hookean"; }
  std::vector<std::string> coefficient_names() const override { return {"mu", "lambda", "kappa"}; }
  Eigen::VectorXd coefficients() const override { return c_; }
  void set_coefficients(const Eigen::VectorXd& c) override { c_ = c; }
  bool linear_in_coefficients() const override { return !std::isfinite(s_); }
  std::unique_ptr<fem::Law> clone() const override { return std::make_unique<TestingLaw>(*this); }

  void evaluate(const fem::LawInput& in, const fem::LawRequest& req, fem::LawOutput& out) const override {
    const double mu = c_(0), lambda = c_(1), kappa = c_(2);
    const Mat2& F = in.F;
    const Vec2 a = in.Q.col(0), Fa = F * a;
    const double J = F.determinant(), lnJ = std::log(J);
    const Mat2 Finv = F.inverse(), FinvT = Finv.transpose();
    const double e = Fa.squaredNorm() - 1;  // a·C·a − 1
    const Mat2 aa = a * a.transpose();
    const Mat2 dP_dmu = F - FinvT, dP_dlambda = lnJ * FinvT, dP_dkappa = 2 * e * F * aa;
    const Mat2 P0 = mu * dP_dmu + lambda * dP_dlambda + kappa * dP_dkappa;
    const Eigen::Vector3d dW0_dc(0.5 * ((F.transpose() * F).trace() - 2 - 2 * lnJ), 0.5 * lnJ * lnJ, 0.5 * e * e);
    const double W0 = c_.dot(dW0_dc);
    const double g = std::isfinite(s_) ? std::exp(-W0 / s_) : 1.0;  // dW/dW0
    out.P = g * P0;
    out.lambda3 = 1;
    if (req.tangent) {
      Mat4 A0;
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
          for (int k = 0; k < 2; ++k)
            for (int l = 0; l < 2; ++l)
              A0(2 * i + j, 2 * k + l) = mu * (i == k) * (j == l) + (mu - lambda * lnJ) * Finv(j, k) * Finv(l, i) +
                                         lambda * FinvT(i, j) * FinvT(k, l) +
                                         2 * kappa * ((i == k) * a(l) * a(j) * e + 2 * Fa(i) * a(j) * Fa(k) * a(l));
      out.A = g * A0;
      if (std::isfinite(s_)) out.A -= g / s_ * flatten(P0) * flatten(P0).transpose();
    }
    if (req.sensitivities) {
      out.dP_dc = {dP_dmu, dP_dlambda, dP_dkappa};
      for (int k = 0; k < 3; ++k) {
        out.dP_dc[k] *= g;
        if (std::isfinite(s_)) out.dP_dc[k] -= g / s_ * dW0_dc(k) * P0;
      }
    }
  }

 private:
  Eigen::VectorXd c_;
  double s_;
};

}  // namespace tricot::test
