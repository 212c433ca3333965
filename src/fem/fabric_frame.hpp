// The kinematic frame shared by the fabric laws (THEORY §5 "FE use"; docs/theory/fabric.md §3):
//   E = ½(FᵀF − I),  E_m = Qᵀ E Q  (εC = E_m11, εW = E_m22, E_CW = E_m12),
//   T = [[F_C, 2 G_s E_CW], [2 G_s E_CW, F_W]]  (material frame, N/mm),
//   P = R Q T Qᵀ  (F = R U: the material frame turns with R).
// Private to tricot_fem: ResponseSurface and ReferenceFabric differ only in F_C, F_W.
#pragma once

#include <Eigen/LU>
#include <cmath>

#include "tricot/core/kinematics.hpp"
#include "tricot/fem/law.hpp"

namespace tricot::fem::detail {

struct FabricKinematics {
  PolarDecomposition polar;
  PolarJacobians J_polar;  ///< only when built with tangent = true
  Mat2 E_m;                ///< Green–Lagrange strain in the material frame
  Mat4 J_Em_F;             ///< ∂E_m/∂F, only when built with tangent = true
};

/// The forces of a fabric law at (εC, εW) and their partial derivatives.
struct FabricForces {
  double F_C = 0, F_W = 0;
  double dFC_deC = 0, dFC_deW = 0, dFW_deC = 0, dFW_deW = 0;
};

inline FabricKinematics fabric_kinematics(const LawInput& in, bool tangent) {
  FabricKinematics k;
  k.polar = polar_decomposition(in.F, tangent ? &k.J_polar : nullptr);
  Mat4 J_E_F;
  const Mat2 E = green_lagrange(in.F, tangent ? &J_E_F : nullptr);
  k.E_m = in.Q.transpose() * E * in.Q;
  if (tangent) k.J_Em_F = sandwich_product(in.Q.transpose(), in.Q) * J_E_F;
  return k;
}

/// T in the material frame.
inline Mat2 fabric_T(const FabricForces& f, double G_s, const Mat2& E_m) {
  Mat2 T;
  T << f.F_C, G_s * (E_m(0, 1) + E_m(1, 0)), G_s * (E_m(0, 1) + E_m(1, 0)), f.F_W;
  return T;
}

/// P = R Q T Qᵀ, A = ∂P/∂F (exact: ∂R/∂F from the closed-form polar decomposition), λ3 = 1/det F
/// (incompressible knit; reported only, P does not depend on it).
inline void fabric_stress(const LawInput& in, const FabricKinematics& k, const FabricForces& f, double G_s,
                          bool tangent, LawOutput& out) {
  const Mat2& Q = in.Q;
  const Mat2 M = Q * fabric_T(f, G_s, k.E_m) * Q.transpose();
  out.P = k.polar.R * M;
  out.lambda3 = 1 / in.F.determinant();
  if (tangent) {
    Mat4 J_T_Em = Mat4::Zero();
    J_T_Em(0, 0) = f.dFC_deC;
    J_T_Em(0, 3) = f.dFC_deW;
    J_T_Em(3, 0) = f.dFW_deC;
    J_T_Em(3, 3) = f.dFW_deW;
    J_T_Em(1, 1) = J_T_Em(1, 2) = J_T_Em(2, 1) = J_T_Em(2, 2) = G_s;
    // dP = dR M + R Q dT Qᵀ.
    out.A = right_product(M) * k.J_polar.R_F +
            left_product(k.polar.R) * sandwich_product(Q, Q.transpose()) * J_T_Em * k.J_Em_F;
  }
}

/// ∂P/∂c for a coefficient that enters T as T_c (material frame): R Q T_c Qᵀ.
inline Mat2 fabric_basis(const LawInput& in, const FabricKinematics& k, const Mat2& T_c) {
  return k.polar.R * in.Q * T_c * in.Q.transpose();
}


}  // namespace tricot::fem::detail
