// Synthetic "true" knit (see reference_fabric.hpp, docs/theory/fabric.md §4).
#include "tricot/fem/reference_fabric.hpp"

#include <array>
#include <cmath>

#include "fabric_frame.hpp"
#include "invalid_state.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

constexpr int kCoefficients = 13;

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
    throw InputError(Location{"", 0, std::string("law.reference_fabric.") + key}, "out of range", std::to_string(v),
                     range);
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
  require(k_P >= 0, "k_P", k_P, ">= 0 N/mm");
  require(k_P * k_P < k_C * k_W, "k_P", k_P, "k_P^2 < k_C k_W (a stable knit at rest)");
  require(k_J >= 0, "k_J", k_J, ">= 0 N/mm");
  require(eps_J > 0, "eps_J", eps_J, "> 0");
  require(s_J > 0, "s_J", s_J, "> 0");
  require(G_s > 0, "G_s", G_s, "> 0 N/mm");
}

ReferenceFabric::ReferenceFabric(const ReferenceFabricParameters& p) : p_(p) { p_.validate(); }

std::vector<std::string> ReferenceFabric::coefficient_names() const {
  return {"k_C", "k_CL", "eps_CL", "s_CL", "k_W", "k_WL", "eps_WL", "s_WL", "k_X", "k_P", "k_J", "eps_J", "s_J"};
}

Eigen::VectorXd ReferenceFabric::coefficients() const {
  Eigen::VectorXd c(kCoefficients);
  c << p_.k_C, p_.k_CL, p_.eps_CL, p_.s_CL, p_.k_W, p_.k_WL, p_.eps_WL, p_.s_WL, p_.k_X, p_.k_P, p_.k_J, p_.eps_J,
      p_.s_J;
  return c;
}

void ReferenceFabric::set_coefficients(const Eigen::VectorXd& c) {
  if (c.size() != kCoefficients)
    throw InputError(Location{"", 0, "law.reference_fabric"}, "wrong number of reference-fabric coefficients",
                     std::to_string(c.size()), std::to_string(kCoefficients));
  ReferenceFabricParameters p = p_;
  p.k_C = c(0), p.k_CL = c(1), p.eps_CL = c(2), p.s_CL = c(3);
  p.k_W = c(4), p.k_WL = c(5), p.eps_WL = c(6), p.s_WL = c(7), p.k_X = c(8);
  p.k_P = c(9), p.k_J = c(10), p.eps_J = c(11), p.s_J = c(12);
  p.validate();
  p_ = p;
}

namespace {

/// Everything one evaluation needs at (εC, εW): forces, their strain derivatives, and the pieces of
/// the coefficient derivatives.
struct Knit {
  Locking LC, LW;  // locking of course and wale
  Locking JC, JW;  // jamming, as L(−ε; k_J, eps_J, s_J): the force term is −J.v, its slope +J.d_eps
  double s = 0;    // εC + εW
  detail::FabricForces f;
};

Knit knit(const ReferenceFabricParameters& p, double eC, double eW) {
  Knit k;
  k.LC = locking(eC, p.k_CL, p.eps_CL, p.s_CL);
  k.LW = locking(eW, p.k_WL, p.eps_WL, p.s_WL);
  k.JC = locking(-eC, p.k_J, p.eps_J, p.s_J);
  k.JW = locking(-eW, p.k_J, p.eps_J, p.s_J);
  k.s = eC + eW;
  const double X = p.k_X / 3 * k.s * k.s * k.s, dX = p.k_X * k.s * k.s;
  k.f.F_C = p.k_C * eC + k.LC.v - k.JC.v + p.k_P * eW + X;
  k.f.F_W = p.k_W * eW + k.LW.v - k.JW.v + p.k_P * eC + X;
  k.f.dFC_deC = p.k_C + k.LC.d_eps + k.JC.d_eps + dX;
  k.f.dFC_deW = p.k_P + dX;
  k.f.dFW_deC = p.k_P + dX;
  k.f.dFW_deW = p.k_W + k.LW.d_eps + k.JW.d_eps + dX;
  return k;
}

}  // namespace

Vec2 ReferenceFabric::forces(double eC, double eW) const {
  const Knit k = knit(p_, eC, eW);
  return {k.f.F_C, k.f.F_W};
}

Mat2 ReferenceFabric::force_jacobian(double eC, double eW) const {
  const Knit k = knit(p_, eC, eW);
  Mat2 A;
  A << k.f.dFC_deC, k.f.dFC_deW, k.f.dFW_deC, k.f.dFW_deW;
  return A;
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
  const Knit n = knit(p_, eC, eW);
  detail::fabric_stress(in, k, n.f, p_.G_s, req.tangent, out);
  if (req.sensitivities) {
    // ∂T/∂c_k is diagonal: (∂F_C/∂c_k, ∂F_W/∂c_k); then ∂P/∂c_k = R Q ∂T/∂c_k Qᵀ.
    const double s3 = n.s * n.s * n.s / 3;
    const std::array<Vec2, kCoefficients> dF = {Vec2(eC, 0),
                                                Vec2(n.LC.d_k, 0),
                                                Vec2(n.LC.d_e0, 0),
                                                Vec2(n.LC.d_s, 0),
                                                Vec2(0, eW),
                                                Vec2(0, n.LW.d_k),
                                                Vec2(0, n.LW.d_e0),
                                                Vec2(0, n.LW.d_s),
                                                Vec2(s3, s3),
                                                Vec2(eW, eC),
                                                Vec2(-n.JC.d_k, -n.JW.d_k),
                                                Vec2(-n.JC.d_e0, -n.JW.d_e0),
                                                Vec2(-n.JC.d_s, -n.JW.d_s)};
    out.dP_dc.resize(kCoefficients);
    for (int i = 0; i < kCoefficients; ++i) out.dP_dc[i] = detail::fabric_basis(in, k, dF[i].asDiagonal());
  } else {
    out.dP_dc.clear();
  }
}

}  // namespace tricot::fem
