// Compressible neo-Hookean membrane in plane stress (see neo_hookean.hpp).
#include "tricot/fem/neo_hookean.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "invalid_state.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

void check(double mu, double lambda) {
  if (!(mu > 0) || !std::isfinite(mu))
    throw InputError(Location{"", 0, "law.neo_hookean.mu"}, "out of range", std::to_string(mu), "> 0 N/mm");
  if (!(lambda >= 0) || !std::isfinite(lambda))
    throw InputError(Location{"", 0, "law.neo_hookean.lambda"}, "out of range", std::to_string(lambda), ">= 0 N/mm");
}

}  // namespace

const char* to_string(Kinematics k) { return k == Kinematics::plane_strain ? "plane_strain" : "plane_stress"; }

NeoHookean::NeoHookean(double mu, double lambda, Kinematics kinematics)
    : mu_(mu), lambda_(lambda), kinematics_(kinematics) {
  check(mu, lambda);
}

NeoHookean::NeoHookean(YoungPoisson e, Kinematics kinematics)
    : mu_(0), lambda_(0), kinematics_(kinematics), young_poisson_(true) {
  set_coefficients(Eigen::Vector2d(e.E, e.nu));
}

std::vector<std::string> NeoHookean::coefficient_names() const {
  return young_poisson_ ? std::vector<std::string>{"E", "nu"} : std::vector<std::string>{"mu", "lambda"};
}

Eigen::VectorXd NeoHookean::coefficients() const {
  return young_poisson_ ? Eigen::Vector2d(E_, nu_) : Eigen::Vector2d(mu_, lambda_);
}

void NeoHookean::set_coefficients(const Eigen::VectorXd& c) {
  if (c.size() != 2)
    throw InputError(Location{"", 0, "law.neo_hookean"}, "wrong number of neo-Hookean coefficients",
                     std::to_string(c.size()), "2");
  if (!young_poisson_) {
    check(c(0), c(1));
    mu_ = c(0);
    lambda_ = c(1);
    return;
  }
  if (!(c(0) > 0) || !std::isfinite(c(0)))
    throw InputError(Location{"", 0, "law.neo_hookean.E"}, "out of range", std::to_string(c(0)), "> 0 N/mm");
  if (!(c(1) > -1 && c(1) < 0.5))
    throw InputError(Location{"", 0, "law.neo_hookean.nu"}, "out of range", std::to_string(c(1)), "in (-1, 0.5)");
  E_ = c(0), nu_ = c(1);
  mu_ = E_ / (2 * (1 + nu_));
  lambda_ = E_ * nu_ / ((1 + nu_) * (1 - 2 * nu_));
}

void NeoHookean::evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const {
  const Mat2& F = in.F;
  const double detF = F.determinant();
  if (detail::invalid_state(detF, req, 2, out)) return;
  const double mu = mu_, lam = lambda_;
  if (kinematics_ == Kinematics::plane_strain) {
    // C33 = 1: P = μ (F − F⁻ᵀ) + λ ln J F⁻ᵀ; dP = μ dF + (μ − λ ln J) F⁻ᵀ dFᵀ F⁻ᵀ + λ (F⁻ᵀ : dF) F⁻ᵀ.
    const Mat2 Fit = F.inverse().transpose();
    const double lnJ = std::log(detF);
    out.P = mu * (F - Fit) + lam * lnJ * Fit;
    out.lambda3 = 1;
    if (req.tangent)
      for (int k = 0; k < 2; ++k)
        for (int l = 0; l < 2; ++l) {
          Mat2 dF = Mat2::Zero();
          dF(k, l) = 1;
          out.A.col(2 * k + l) =
              flatten(mu * dF + (mu - lam * lnJ) * Fit * dF.transpose() * Fit + lam * Fit(k, l) * Fit);
        }
    out.dP_dc.clear();
    if (req.sensitivities) out.dP_dc = {F - Fit, lnJ * Fit};
    to_young_poisson(out.dP_dc);
    return;
  }
  const double lnJ2 = 2 * std::log(detF);
  // σ33 = 0: g(s) = μ (eˢ − 1) + λ/2 (ln J2 + s) = 0 with s = ln C33. g is increasing and convex, so
  // Newton from s = 0 converges monotonically after at most one overshoot.
  double s = 0;
  for (int it = 0; it < 100; ++it) {
    const double g = mu * (std::exp(s) - 1) + 0.5 * lam * (lnJ2 + s);
    const double ds = -g / (mu * std::exp(s) + 0.5 * lam);
    s += ds;
    if (std::abs(ds) <= 1e-15 * std::max(1.0, std::abs(s))) break;
  }
  const double t = std::exp(s);         // C33 = λ3²
  const double lnJ = 0.5 * (lnJ2 + s);  // ln of the 3-D volume ratio
  const double h = mu * t + 0.5 * lam;  // ∂g/∂s
  const Mat2 Fit = F.inverse().transpose();
  out.P = mu * (F - t * Fit);
  out.lambda3 = std::sqrt(t);

  if (req.tangent) {
    // dP = μ (dF − dt F⁻ᵀ + t F⁻ᵀ dFᵀ F⁻ᵀ), dt = t ds, ds = −λ (F⁻ᵀ : dF) / h.
    for (int k = 0; k < 2; ++k)
      for (int l = 0; l < 2; ++l) {
        Mat2 dF = Mat2::Zero();
        dF(k, l) = 1;
        const double dt = t * (-lam * Fit(k, l) / h);
        out.A.col(2 * k + l) = flatten(mu * (dF - dt * Fit + t * Fit * dF.transpose() * Fit));
      }
  }
  if (req.sensitivities) {
    // ∂s/∂μ = −(t − 1)/h, ∂s/∂λ = −ln J / h (implicit differentiation of g = 0).
    out.dP_dc.resize(2);
    out.dP_dc[0] = (F - t * Fit) - mu * t * (-(t - 1) / h) * Fit;
    out.dP_dc[1] = -mu * t * (-lnJ / h) * Fit;
    to_young_poisson(out.dP_dc);
  } else {
    out.dP_dc.clear();
  }
}

void NeoHookean::to_young_poisson(std::vector<Mat2>& dP) const {
  if (!young_poisson_ || dP.size() != 2) return;
  // ∂(μ, λ)/∂(E, ν): μ = E/(2(1 + ν)), λ = Eν/((1 + ν)(1 − 2ν)).
  const double a = 1 + nu_, b = 1 - 2 * nu_;
  const double dmu_dE = 1 / (2 * a), dmu_dnu = -E_ / (2 * a * a);
  const double dl_dE = nu_ / (a * b), dl_dnu = E_ * (1 + 2 * nu_ * nu_) / (a * a * b * b);
  const Mat2 dmu = dP[0], dl = dP[1];
  dP[0] = dmu_dE * dmu + dl_dE * dl;
  dP[1] = dmu_dnu * dmu + dl_dnu * dl;
}

}  // namespace tricot::fem
