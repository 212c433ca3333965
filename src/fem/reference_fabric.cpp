// Synthetic "true" knit (see reference_fabric.hpp, docs/theory/fabric.md §4).
#include "tricot/fem/reference_fabric.hpp"

#include <array>
#include <cmath>

#include "fabric_frame.hpp"
#include "invalid_state.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

constexpr int kCoefficients = 9;

/// L(ε) = k s (exp((ε − e0)/s) − exp(−e0/s)): the locking term, its slope and its derivatives in (k, e0, s).
struct Locking {
  double v, d_eps, d_k, d_e0, d_s;
};
Locking locking(double eps, double k, double e0, double s) {
  const double e1 = std::exp((eps - e0) / s), e2 = std::exp(-e0 / s);
  return {k * s * (e1 - e2), k * e1, s * (e1 - e2), k * (e2 - e1), k * (e1 - e2) - k / s * ((eps - e0) * e1 + e0 * e2)};
}

void require(bool ok, const char* key, double v, const char* range) {
  if (!ok || !std::isfinite(v))
    throw InputError(Location{"", 0, std::string("material.") + key}, "out of range", std::to_string(v), range);
}

}  // namespace

void ReferenceFabricParameters::validate() const {
  require(k_C > 0, "k_C", k_C, "> 0 N/mm");
  require(k_CL >= 0, "k_CL", k_CL, ">= 0 N/mm");
  require(eps_CL > 0, "eps_CL", eps_CL, "> 0");
  require(s_CL > 0, "s_CL", s_CL, "> 0");
  require(k_W > 0, "k_W", k_W, "> 0 N/mm");
  require(k_WL >= 0, "k_WL", k_WL, ">= 0 N/mm");
  require(eps_WL > 0, "eps_WL", eps_WL, "> 0");
  require(s_WL > 0, "s_WL", s_WL, "> 0");
  require(k_X >= 0, "k_X", k_X, ">= 0 N/mm");
  require(G_s > 0, "G_s", G_s, "> 0 N/mm");
}

ReferenceFabric::ReferenceFabric(const ReferenceFabricParameters& p) : p_(p) { p_.validate(); }

std::vector<std::string> ReferenceFabric::coefficient_names() const {
  return {"k_C", "k_CL", "eps_CL", "s_CL", "k_W", "k_WL", "eps_WL", "s_WL", "k_X"};
}

Eigen::VectorXd ReferenceFabric::coefficients() const {
  Eigen::VectorXd c(kCoefficients);
  c << p_.k_C, p_.k_CL, p_.eps_CL, p_.s_CL, p_.k_W, p_.k_WL, p_.eps_WL, p_.s_WL, p_.k_X;
  return c;
}

void ReferenceFabric::set_coefficients(const Eigen::VectorXd& c) {
  if (c.size() != kCoefficients)
    throw InputError(Location{"", 0, "material.coefficients"}, "wrong number of reference-fabric coefficients",
                     std::to_string(c.size()), std::to_string(kCoefficients));
  ReferenceFabricParameters p = p_;
  p.k_C = c(0), p.k_CL = c(1), p.eps_CL = c(2), p.s_CL = c(3);
  p.k_W = c(4), p.k_WL = c(5), p.eps_WL = c(6), p.s_WL = c(7), p.k_X = c(8);
  p.validate();
  p_ = p;
}

Vec2 ReferenceFabric::forces(double eC, double eW) const {
  return {p_.k_C * eC + locking(eC, p_.k_CL, p_.eps_CL, p_.s_CL).v + p_.k_X * eC * eW * eW,
          p_.k_W * eW + locking(eW, p_.k_WL, p_.eps_WL, p_.s_WL).v + p_.k_X * eC * eC * eW};
}

Mat2 ReferenceFabric::material_frame_stress(const LawInput& in) const {
  const detail::FabricKinematics k = detail::fabric_kinematics(in, false);
  const Vec2 f = forces(k.E_m(0, 0), k.E_m(1, 1));
  return detail::fabric_T({f(0), f(1)}, p_.G_s, k.E_m);
}

void ReferenceFabric::evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const {
  if (detail::invalid_state(in.F.determinant(), req, kCoefficients, out)) return;
  const detail::FabricKinematics k = detail::fabric_kinematics(in, req.tangent);
  const double eC = k.E_m(0, 0), eW = k.E_m(1, 1);
  const Locking LC = locking(eC, p_.k_CL, p_.eps_CL, p_.s_CL);
  const Locking LW = locking(eW, p_.k_WL, p_.eps_WL, p_.s_WL);
  detail::FabricForces f;
  f.F_C = p_.k_C * eC + LC.v + p_.k_X * eC * eW * eW;
  f.F_W = p_.k_W * eW + LW.v + p_.k_X * eC * eC * eW;
  f.dFC_deC = p_.k_C + LC.d_eps + p_.k_X * eW * eW;
  f.dFC_deW = 2 * p_.k_X * eC * eW;
  f.dFW_deC = 2 * p_.k_X * eC * eW;
  f.dFW_deW = p_.k_W + LW.d_eps + p_.k_X * eC * eC;
  detail::fabric_stress(in, k, f, p_.G_s, req.tangent, out);
  if (req.sensitivities) {
    // ∂T/∂c_k is diagonal: (∂F_C/∂c_k, ∂F_W/∂c_k); then ∂P/∂c_k = R Q ∂T/∂c_k Qᵀ.
    const std::array<Vec2, kCoefficients> dF = {
        Vec2(eC, 0),        Vec2(LC.d_k, 0), Vec2(LC.d_e0, 0), Vec2(LC.d_s, 0),
        Vec2(0, eW),        Vec2(0, LW.d_k), Vec2(0, LW.d_e0), Vec2(0, LW.d_s),
        Vec2(eC * eW * eW, eC * eC * eW)};
    out.dP_dc.resize(kCoefficients);
    for (int i = 0; i < kCoefficients; ++i) out.dP_dc[i] = detail::fabric_basis(in, k, dF[i].asDiagonal());
  } else {
    out.dP_dc.clear();
  }
}

}  // namespace tricot::fem
