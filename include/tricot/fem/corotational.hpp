// Corotational Eulerian formulation with an orthotropic linear law on the logarithmic strain
// (docs/theory.md §4 eqs. (4)–(6); docs/theory/fabric.md §2).
//
//   F = R U,  H = ln U (reference components),  Ĥ = Qᵀ H Q (material frame: course, wale),
//   τ̂_m = 𝔻 : Ĥ with  τ̂11 = D11 Ĥ11 + D12 Ĥ22,  τ̂22 = D12 Ĥ11 + D22 Ĥ22,  τ̂12 = D66 · 2Ĥ12,
//   τ̂ = Q τ̂_m Qᵀ,  σ = J⁻¹ R τ̂ Rᵀ,  P = J σ F⁻ᵀ = R τ̂ Rᵀ F⁻ᵀ = R τ̂ U⁻¹,
// where J = det F (in-plane area ratio), so that Law::cauchy(F, P) = P Fᵀ/J is the σ above. The
// shear convention is engineering: γ̂ = 2Ĥ12 and τ̂12 = D66 γ̂. All moduli are membrane moduli
// (N/mm: stress × reference thickness). Plane stress: 𝔻 is the in-plane *reduced* stiffness, which
// already encodes σ33 = 0, so P does not depend on λ3. λ3 is reported from the transverse strain of a
// law whose out-of-plane coupling is isotropic: ln λ3 = −κ tr Ĥ with κ = D12 / (√(D11 D22) − D12),
// exact for the isotropic case (κ = λ/(λ + 2μ) of the 3-D Hencky law behind (G, K)).
// Coefficients (identifiable, linear): "D11", "D22", "D12", "D66", so ∂P/∂c_k is exact.
#pragma once

#include "tricot/fem/law.hpp"

namespace tricot::fem {

class CorotationalOrthotropic : public Law {
 public:
  /// In-plane reduced stiffness in the material frame [N/mm]. Throws InputError (key
  /// `law.corotational.D11` …) unless all are finite, D11 > 0, D22 > 0, D66 > 0 and D11 D22 > D12²
  /// (𝔻 positive definite).
  CorotationalOrthotropic(double D11, double D22, double D12, double D66);
  /// Isotropic membrane: τ̂ = K tr(Ĥ) I + 2G dev(Ĥ), i.e. D11 = D22 = K + G, D12 = K − G, D66 = G.
  /// G: shear modulus, K: 2-D (areal) bulk modulus, both N/mm, K > 0, G > 0.
  static CorotationalOrthotropic isotropic(double G, double K);
  /// Isotropic membrane from Young's modulus E [N/mm] and Poisson's ratio ν (plane stress):
  /// D11 = D22 = E/(1 − ν²), D12 = ν E/(1 − ν²), D66 = E/(2(1 + ν)); −1 < ν < 1.
  static CorotationalOrthotropic isotropic_plane_stress(double E, double nu);

  std::string name() const override { return "corotational_orthotropic"; }
  std::vector<std::string> coefficient_names() const override { return {"D11", "D22", "D12", "D66"}; }
  Eigen::VectorXd coefficients() const override;
  void set_coefficients(const Eigen::VectorXd& c) override;
  bool linear_in_coefficients() const override { return true; }
  /// det F ≤ 0 gives NaN outputs (the solver reports an invalid state).
  void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const override;
  std::unique_ptr<Law> clone() const override { return std::make_unique<CorotationalOrthotropic>(*this); }

  /// τ̂_m: the Kirchhoff membrane force in the material frame (course, wale) [N/mm]. It is unchanged
  /// by a rigid rotation of the deformed state.
  Mat2 material_frame_stress(const LawInput& in) const;

 private:
  double D11_, D22_, D12_, D66_;
};

/// Cauchy stress components of a homogeneous simple shear F = [[1, γ], [0, 1]] (det F = 1) for an
/// isotropic linear law of shear modulus G, under three objective rates (docs/theory.md §4).
struct SimpleShearStress {
  double s11 = 0, s22 = 0, s12 = 0;
};
/// Logarithmic (corotational Eulerian) rate, what CorotationalOrthotropic gives:
/// σ12 = 4G asinh(γ/2)/√(4+γ²), σ11 = −σ22 = 2Gγ asinh(γ/2)/√(4+γ²). σ12 → 0 as γ → ∞.
SimpleShearStress simple_shear_log_rate(double G, double gamma);
/// Jaumann rate (hypoelastic, Dienes 1979): σ12 = G sin γ, σ11 = −σ22 = G (1 − cos γ).
SimpleShearStress simple_shear_jaumann(double G, double gamma);
/// Green–Naghdi rate (Dienes 1979), β = atan(γ/2):
/// σ12 = 2G cos 2β (2β − 2 tan 2β ln cos β − tan β),
/// σ11 = −σ22 = 4G (cos 2β ln cos β + β sin 2β − sin² β).
SimpleShearStress simple_shear_green_naghdi(double G, double gamma);

}  // namespace tricot::fem
