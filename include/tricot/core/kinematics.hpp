// 2-D finite-strain kinematics in closed form (docs/theory.md §4, docs/theory/fabric.md §1): polar
// decomposition F = R U, the logarithmic strain ln U, the Green–Lagrange strain E, and their exact
// derivatives. Jacobians follow manif's naming (J_out_in = ∂out/∂in) and the Mat4 index convention of
// core/types.hpp: J(2i+j, 2k+l) = ∂out_ij/∂in_kl. Optional Jacobian outputs are computed only when a
// pointer is given. Every function is pure (thread-safe).
#pragma once

#include "tricot/core/types.hpp"

namespace tricot {

/// F = R U with R = rot(θ) and U symmetric positive definite (docs/theory.md §4).
struct PolarDecomposition {
  double theta = 0;           ///< rotation angle [rad], θ = atan2(F21 − F12, F11 + F22) ∈ (−π, π]
  Mat2 R = Mat2::Identity();  ///< rotation [[cos θ, −sin θ], [sin θ, cos θ]]
  Mat2 U = Mat2::Identity();  ///< right stretch U = Rᵀ F (symmetric by construction of θ)
};

/// Derivatives of the polar decomposition with respect to F.
struct PolarJacobians {
  Vec4 dtheta_dF = Vec4::Zero();  ///< ∂θ/∂F_kl at index 2k+l
  Mat4 dR_dF = Mat4::Zero();      ///< ∂R/∂F
  Mat4 dU_dF = Mat4::Zero();      ///< ∂U/∂F
};

/// Closed-form polar decomposition of a 2×2 F with det F > 0 (then tr U = |(F11+F22, F21−F12)| > 0
/// and det U = det F > 0, so U is SPD). With det F ≤ 0 the result is not a polar decomposition.
/// dθ = (x dy − y dx)/(x² + y²) with x = F11 + F22, y = F21 − F12; dR = R W dθ, W = [[0,−1],[1,0]];
/// dU = Rᵀ dF − W U dθ.
PolarDecomposition polar_decomposition(const Mat2& F, PolarJacobians* J = nullptr);

/// (ln a − ln b)/(a − b) for a, b > 0, equal to 1/a at a = b. Computed as atanh(t)/(t m) with
/// m = (a+b)/2, t = (a−b)/(a+b), and a series in t² when |t| is small, so it is accurate to round-off
/// for every a, b (no cancellation near a = b).
double log_divided_difference(double a, double b);

/// Matrix logarithm of a 2×2 U with real positive eigenvalues (SPD in practice), in closed form
/// (Cayley–Hamilton): ln U = ½ ln(det U) I + (ln λ1 − ln λ2)/(λ1 − λ2) · (U − m I), m = tr U / 2,
/// λ1,2 = m ± d, d² = ((U11 − U22)/2)² + U12 U21. It is the primary matrix function, so J_logU_U is
/// the Fréchet derivative in every direction (Daleckii–Krein), and at repeated eigenvalues
/// (U = λ I) it is exactly (1/λ) I₄. The divided difference is a function of d²/m², evaluated by a
/// series near 0, so the derivative is smooth through the equal-eigenvalue point.
Mat2 log_spd(const Mat2& U, Mat4* J_logU_U = nullptr);

/// Green–Lagrange strain E = ½(Fᵀ F − I) (docs/theory.md §4); ∂E_ij/∂F_kl = ½(δ_jl F_ki + δ_il F_kj).
Mat2 green_lagrange(const Mat2& F, Mat4* J_E_F = nullptr);

/// ∂(A X)/∂X as a Mat4 (left multiplication by A), for chain rules on 2×2 tensors.
Mat4 left_product(const Mat2& A);
/// ∂(X B)/∂X as a Mat4 (right multiplication by B).
Mat4 right_product(const Mat2& B);
/// ∂(A X B)/∂X = left_product(A) · right_product(B). With A = Qᵀ, B = Q it maps a tensor's reference
/// components to its material-frame components Qᵀ X Q.
Mat4 sandwich_product(const Mat2& A, const Mat2& B);

}  // namespace tricot
