// The kinematic frame shared by the fabric laws (docs/theory.md §5 "FE use"; docs/theory/fabric.md §3):
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
  /// The rotation of F = R U: cos θ = (F11 + F22)/r, sin θ = (F21 − F12)/r, r = |(F11 + F22, F21 − F12)|
  /// (> 0 where det F > 0): tricot::polar_decomposition's R without atan2 and sincos.
  Mat2 R;
  Vec4 dtheta_dF;  ///< ∂θ/∂F (row-major flattening), only when built with tangent = true
  Mat2 E_m;      ///< Green–Lagrange strain in the material frame
  Mat4 J_Em_F;   ///< ∂E_m/∂F, only when built with tangent = true
};

/// The forces of a fabric law at (εC, εW) and their partial derivatives.
struct FabricForces {
  double F_C = 0, F_W = 0;
  double dFC_deC = 0, dFC_deW = 0, dFW_deC = 0, dFW_deW = 0;
};

inline FabricKinematics fabric_kinematics(const LawInput& in, bool tangent) {
  FabricKinematics k;
  const Mat2& F = in.F;
  const double x = F(0, 0) + F(1, 1), y = F(1, 0) - F(0, 1);
  const double r2 = x * x + y * y, inv_r = 1 / std::sqrt(r2);
  const double c = x * inv_r, s = y * inv_r;
  k.R << c, -s, s, c;
  // E_m = Qᵀ E Q = ½(GᵀG − I) with G = F Q; ∂E_m(i, j)/∂F(k, l) = ½(Q(l, i) G(k, j) + G(k, i) Q(l, j)).
  const Mat2 G = F * in.Q;
  k.E_m = 0.5 * (G.transpose() * G - Mat2::Identity());
  if (tangent) {
    k.dtheta_dF = Vec4(-y, -x, x, -y) / r2;
    const Mat2& Q = in.Q;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int kk = 0; kk < 2; ++kk)
          for (int l = 0; l < 2; ++l) k.J_Em_F(2 * i + j, 2 * kk + l) = 0.5 * (Q(l, i) * G(kk, j) + G(kk, i) * Q(l, j));
  }
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
  // P = R M entry by entry: as one 2 × 2 product GCC stored it in two 16-byte halves and reloaded it
  // as one 32-byte vector (a store-forwarding stall, ~1/3 of this function).
  const Mat2& R = k.R;
  out.P << R(0, 0) * M(0, 0) + R(0, 1) * M(1, 0), R(0, 0) * M(0, 1) + R(0, 1) * M(1, 1),
      R(1, 0) * M(0, 0) + R(1, 1) * M(1, 0), R(1, 0) * M(0, 1) + R(1, 1) * M(1, 1);
  out.lambda3 = 1 / in.F.determinant();
  if (tangent) {
    // dP = dR M + R Q dT Qᵀ with dR = R W dθ (W = [[0, −1], [1, 0]]): the first term is the rank-one
    // flatten(R W M) ⊗ ∂θ/∂F; the second maps each column X_col of X = ∂T/∂E_m ∂E_m/∂F (as a 2 × 2) to
    // R Q X_col Qᵀ.
    Mat2 RW;
    RW << k.R(0, 1), -k.R(0, 0), k.R(1, 1), -k.R(1, 0);
    out.A.noalias() = flatten(RW * M) * k.dtheta_dF.transpose();
    const Mat4& J = k.J_Em_F;
    Eigen::Matrix<double, 3, 4> X;  // rows 0, 1 (= 2), 3 of ∂T/∂F
    X.row(0) = f.dFC_deC * J.row(0) + f.dFC_deW * J.row(3);
    X.row(1) = G_s * (J.row(1) + J.row(2));
    X.row(2) = f.dFW_deC * J.row(0) + f.dFW_deW * J.row(3);
    const Mat2 RQ = k.R * Q;
    for (int c = 0; c < 4; ++c) {
      Mat2 Xc;
      Xc << X(0, c), X(1, c), X(1, c), X(2, c);
      out.A.col(c) += flatten(RQ * Xc * Q.transpose());
    }
  }
}

/// ∂P/∂c for a coefficient c that enters T linearly, dT_dc = ∂T/∂c (material frame): R Q dT_dc Qᵀ.
inline Mat2 fabric_basis(const LawInput& in, const FabricKinematics& k, const Mat2& dT_dc) {
  return k.R * in.Q * dT_dc * in.Q.transpose();
}

}  // namespace tricot::fem::detail
