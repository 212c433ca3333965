// Corotational Eulerian orthotropic law (see corotational.hpp, docs/theory.md §4).
#include "tricot/fem/corotational.hpp"

#include <Eigen/LU>
#include <array>
#include <cmath>

#include "invalid_state.hpp"
#include "tricot/core/error.hpp"
#include "tricot/core/kinematics.hpp"

namespace tricot::fem {
namespace {

void check(double D11, double D22, double D12, double D66) {
  const std::array<std::pair<const char*, double>, 4> c = {{{"law.corotational.D11", D11},
                                                            {"law.corotational.D22", D22},
                                                            {"law.corotational.D12", D12},
                                                            {"law.corotational.D66", D66}}};
  for (const auto& [key, v] : c)
    if (!std::isfinite(v))
      throw InputError(Location{"", 0, key}, "not a finite number", std::to_string(v), "finite N/mm");
  if (!(D11 > 0))
    throw InputError(Location{"", 0, "law.corotational.D11"}, "out of range", std::to_string(D11), "> 0 N/mm");
  if (!(D22 > 0))
    throw InputError(Location{"", 0, "law.corotational.D22"}, "out of range", std::to_string(D22), "> 0 N/mm");
  if (!(D66 > 0))
    throw InputError(Location{"", 0, "law.corotational.D66"}, "out of range", std::to_string(D66), "> 0 N/mm");
  if (!(D11 * D22 > D12 * D12))
    throw InputError(Location{"", 0, "law.corotational.D12"}, "stiffness is not positive definite", std::to_string(D12),
                     "D12² < D11·D22");
}

/// 𝔻 as a Mat4 on flattened material-frame components: τ̂11 = D11 Ĥ11 + D12 Ĥ22, τ̂22 = D12 Ĥ11 +
/// D22 Ĥ22, τ̂12 = τ̂21 = D66 (Ĥ12 + Ĥ21) (engineering shear).
Mat4 stiffness(double D11, double D22, double D12, double D66) {
  Mat4 D = Mat4::Zero();
  D(0, 0) = D11;
  D(0, 3) = D12;
  D(3, 0) = D12;
  D(3, 3) = D22;
  D(1, 1) = D(1, 2) = D(2, 1) = D(2, 2) = D66;
  return D;
}

}  // namespace

CorotationalOrthotropic::CorotationalOrthotropic(double D11, double D22, double D12, double D66)
    : D11_(D11), D22_(D22), D12_(D12), D66_(D66) {
  check(D11, D22, D12, D66);
}

CorotationalOrthotropic CorotationalOrthotropic::isotropic(double G, double K) {
  if (!(G > 0) || !std::isfinite(G))
    throw InputError(Location{"", 0, "law.corotational.G"}, "out of range", std::to_string(G), "> 0 N/mm");
  if (!(K > 0) || !std::isfinite(K))
    throw InputError(Location{"", 0, "law.corotational.K"}, "out of range", std::to_string(K), "> 0 N/mm");
  return {K + G, K + G, K - G, G};
}

CorotationalOrthotropic CorotationalOrthotropic::isotropic_plane_stress(double E, double nu) {
  if (!(E > 0) || !std::isfinite(E))
    throw InputError(Location{"", 0, "law.corotational.E"}, "out of range", std::to_string(E), "> 0 N/mm");
  if (!(nu > -1 && nu < 1))
    throw InputError(Location{"", 0, "law.corotational.nu"}, "out of range", std::to_string(nu), "-1 < nu < 1");
  const double Dp = E / (1 - nu * nu);
  return {Dp, Dp, nu * Dp, E / (2 * (1 + nu))};
}

Eigen::VectorXd CorotationalOrthotropic::coefficients() const { return Eigen::Vector4d(D11_, D22_, D12_, D66_); }

void CorotationalOrthotropic::set_coefficients(const Eigen::VectorXd& c) {
  if (c.size() != 4)
    throw InputError(Location{"", 0, "law.corotational"}, "wrong number of corotational coefficients",
                     std::to_string(c.size()), "4 (D11, D22, D12, D66)");
  check(c(0), c(1), c(2), c(3));
  D11_ = c(0);
  D22_ = c(1);
  D12_ = c(2);
  D66_ = c(3);
}

Mat2 CorotationalOrthotropic::material_frame_stress(const LawInput& in) const {
  const Mat2 H = log_spd(polar_decomposition(in.F).U);
  const Mat2 Hm = in.Q.transpose() * H * in.Q;
  return unflatten(stiffness(D11_, D22_, D12_, D66_) * flatten(Hm));
}

void CorotationalOrthotropic::evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const {
  const double J = in.F.determinant();
  if (detail::invalid_state(J, req, 4, out)) return;
  const Mat2& Q = in.Q;

  // docs/theory.md §4: F = R U, Ĥ = Qᵀ ln U Q, τ̂_m = 𝔻 : Ĥ, τ̂ = Q τ̂_m Qᵀ, P = R τ̂ U⁻¹.
  PolarJacobians JP;
  const PolarDecomposition p = polar_decomposition(in.F, req.tangent ? &JP : nullptr);
  Mat4 dH_dU;
  const Mat2 H = log_spd(p.U, req.tangent ? &dH_dU : nullptr);
  const Mat2 Hm = Q.transpose() * H * Q;
  const Mat4 Dm = stiffness(D11_, D22_, D12_, D66_);
  const Mat2 tau_hat = Q * unflatten(Dm * flatten(Hm)) * Q.transpose();
  const Mat2 U_inv = p.U.inverse();
  const Mat2 S = tau_hat * U_inv;
  out.P = p.R * S;

  const double kappa = D12_ / (std::sqrt(D11_ * D22_) - D12_);
  out.lambda3 = std::exp(-kappa * Hm.trace());

  if (req.tangent) {
    // dP = dR S + R dS, dS = dτ̂ U⁻¹ − τ̂ U⁻¹ dU U⁻¹, dτ̂ = 𝔻_ref : (∂lnU/∂U) : dU.
    const Mat4 D_ref = sandwich_product(Q, Q.transpose()) * Dm * sandwich_product(Q.transpose(), Q);
    const Mat4 dtau_dF = D_ref * dH_dU * JP.dU_dF;
    const Mat4 dUinv_dF = -sandwich_product(U_inv, U_inv) * JP.dU_dF;
    const Mat4 dS_dF = right_product(U_inv) * dtau_dF + left_product(tau_hat) * dUinv_dF;
    out.A = right_product(S) * JP.dR_dF + left_product(p.R) * dS_dF;
  }
  if (req.sensitivities) {
    // P is linear in (D11, D22, D12, D66): ∂P/∂c_k = R Q (∂τ̂_m/∂c_k) Qᵀ U⁻¹.
    std::array<Mat2, 4> dtau;
    dtau[0] << Hm(0, 0), 0, 0, 0;
    dtau[1] << 0, 0, 0, Hm(1, 1);
    dtau[2] << Hm(1, 1), 0, 0, Hm(0, 0);
    dtau[3] << 0, Hm(0, 1) + Hm(1, 0), Hm(0, 1) + Hm(1, 0), 0;
    out.dP_dc.resize(4);
    for (int k = 0; k < 4; ++k) out.dP_dc[k] = p.R * Q * dtau[k] * Q.transpose() * U_inv;
  } else {
    out.dP_dc.clear();
  }
}

SimpleShearStress simple_shear_log_rate(double G, double gamma) {
  const double f = std::asinh(gamma / 2) / std::sqrt(4 + gamma * gamma);
  return {2 * G * gamma * f, -2 * G * gamma * f, 4 * G * f};
}

SimpleShearStress simple_shear_jaumann(double G, double gamma) {
  const double s11 = G * (1 - std::cos(gamma));
  return {s11, -s11, G * std::sin(gamma)};
}

SimpleShearStress simple_shear_green_naghdi(double G, double gamma) {
  const double b = std::atan(gamma / 2);
  const double lc = std::log(std::cos(b));
  const double s11 = 4 * G * (std::cos(2 * b) * lc + b * std::sin(2 * b) - std::sin(b) * std::sin(b));
  // cos 2β · tan 2β written as sin 2β: finite through β = π/4 (γ = 2).
  const double s12 = 2 * G * (std::cos(2 * b) * (2 * b - std::tan(b)) - 2 * std::sin(2 * b) * lc);
  return {s11, -s11, s12};
}

}  // namespace tricot::fem
