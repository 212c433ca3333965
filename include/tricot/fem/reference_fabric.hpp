// A synthetic "true" compression-stocking knit for synthetic experiments (docs/theory/fabric.md §4).
// Deliberately NOT in the response-surface family: exponential locking and a cross coupling that
// the separable polynomials of docs/theory.md §5 cannot represent, so an identification against it shows a
// model error, as the paper's did against the real fabric.
//
// Same kinematic frame as ResponseSurface: εC, εW, E_CW are the Green–Lagrange strains in the
// material frame, T = [[F_C, 2 G_s E_CW], [2 G_s E_CW, F_W]], P = R Q T Qᵀ, λ3 = 1/det F. With
// L(ε; k, e, s) = k s (exp((ε − e)/s) − exp(−e/s)) (locking) and s = εC + εW, forces [N/mm]:
//   F_C = k_C εC + L(εC; k_CL, eps_CL, s_CL) − L(−εC; k_J, eps_J, s_J) + k_P εW + (k_X/3) s³
//   F_W = k_W εW + L(εW; k_WL, eps_WL, s_WL) − L(−εW; k_J, eps_J, s_J) + k_P εC + (k_X/3) s³
// - course: the inlaid yarn gives a near-linear response (k_C) up to ~eps_CL, then the loops lock
//   and the stiffness grows like k_CL exp((εC − eps_CL)/s_CL) (J shape);
// - wale: softer, same J shape (k_W, k_WL, eps_WL, s_WL);
// - transverse shrinkage k_P: pulling one direction loads the other (a held width carries a
//   transverse tension; a free side narrows), the knit's "Poisson" effect (paper §3.1.2);
// - jamming k_J, eps_J, s_J: the loops jam when a direction is compressed past ~eps_J, which bounds
//   the shrinkage (GL strain cannot go below −½);
// - coupling k_X: each force stiffens when both directions are stretched (∂F_C/∂εC grows by k_X s²).
// The strain-space tangent [[∂F_C/∂εC, ∂F_C/∂εW], [∂F_W/∂εC, ∂F_W/∂εW]] is symmetric, and positive
// definite over εC ∈ [−0.45, 1.2] × εW ∈ [−0.45, 1] with the defaults (docs/theory/fabric.md §4).
// Defaults: F_C(1, 0) = 0.329 N/mm, F_W(0, 1) = 0.121 N/mm; a free-side wale pull narrows the course
// by −εC/εW = 0.40 (10 %), 0.40 (30 %), 0.39 (60 %); a held width under a wale pull carries
// F_C/F_W ≈ 1.6.
#pragma once

#include "tricot/fem/law.hpp"

namespace tricot::fem {

/// Parameters of ReferenceFabric. Strains are Green–Lagrange along the material axes.
struct ReferenceFabricParameters {
  double k_C = 0.25;    ///< course initial stiffness [N/mm], > 0
  double k_CL = 0.05;   ///< course locking modulus [N/mm], ≥ 0
  double eps_CL = 0.8;  ///< course locking onset [-], > 0
  double s_CL = 0.15;   ///< course locking width [-], > 0
  double k_W = 0.06;    ///< wale initial stiffness [N/mm], > 0
  double k_WL = 0.01;   ///< wale locking modulus [N/mm], ≥ 0
  double eps_WL = 0.7;  ///< wale locking onset [-], > 0
  double s_WL = 0.15;   ///< wale locking width [-], > 0
  double k_X = 0.15;    ///< biaxial coupling [N/mm], ≥ 0
  double k_P = 0.1;     ///< transverse-shrinkage ("Poisson") coupling [N/mm], k_P² < k_C k_W
  double k_J = 0.05;    ///< compression jamming modulus [N/mm], ≥ 0
  double eps_J = 0.2;   ///< jamming onset (compressive GL strain magnitude) [-], > 0
  double s_J = 0.05;    ///< jamming width [-], > 0
  double G_s = 0.05;    ///< fixed in-plane shear stiffness [N/mm], > 0; not a coefficient

  /// Throws InputError (key `law.reference_fabric.<field>`) for a value out of the ranges above or not
  /// finite.
  void validate() const;
};

class ReferenceFabric : public Law {
 public:
  /// Validates `p` (InputError).
  explicit ReferenceFabric(const ReferenceFabricParameters& p = {});

  std::string name() const override { return "reference_fabric"; }
  /// "k_C", "k_CL", "eps_CL", "s_CL", "k_W", "k_WL", "eps_WL", "s_WL", "k_X", "k_P", "k_J", "eps_J",
  /// "s_J" (G_s is fixed).
  std::vector<std::string> coefficient_names() const override;
  Eigen::VectorXd coefficients() const override;
  /// InputError for a wrong size or a value out of range.
  void set_coefficients(const Eigen::VectorXd& c) override;
  /// false (eps_* and s_* enter nonlinearly), but dP_dc is still exact (analytic) for every coefficient.
  bool linear_in_coefficients() const override { return false; }
  /// det F ≤ 0 gives NaN outputs (the solver reports an invalid state).
  void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const override;
  std::unique_ptr<Law> clone() const override { return std::make_unique<ReferenceFabric>(*this); }

  /// (F_C, F_W) [N/mm] at the material-axis Green–Lagrange strains (εC, εW).
  Vec2 forces(double eps_C, double eps_W) const;
  /// ∂(F_C, F_W)/∂(εC, εW): symmetric (a strain-space potential).
  Mat2 force_jacobian(double eps_C, double eps_W) const;
  /// T in the material frame (course, wale) [N/mm]; unchanged by a rigid rotation.
  Mat2 material_frame_stress(const LawInput& in) const;
  const ReferenceFabricParameters& parameters() const { return p_; }

 private:
  ReferenceFabricParameters p_;
};

}  // namespace tricot::fem
