// Compressible neo-Hookean membrane in plane stress or plane strain (docs/theory.md §5):
//   W = μ/2 (I1 − 3) − μ ln J + λ/2 (ln J)²,  S = μ (I − C⁻¹) + λ ln J C⁻¹ (3-D).
// σ33 = 0 fixes t = C33 = λ3² through μ (t − 1) + λ ln J = 0, J² = t det C₂ (a local Newton in
// ln t); then the in-plane S₂ = μ (I − t C₂⁻¹) and P = μ (F − t F⁻ᵀ). Tangent and ∂P/∂(μ, λ) follow
// by implicit differentiation of the σ33 = 0 condition, so they are exact. Forces per unit reference
// length (reference thickness 1): μ and λ in N/mm. Small strain: E = μ(3λ + 2μ)/(λ + μ).
// Plane strain (C33 = 1, a slice of a thick specimen): P = μ (F − F⁻ᵀ) + λ ln J F⁻ᵀ with J = det F,
// linear in (μ, λ).
#pragma once

#include "tricot/fem/law.hpp"

namespace tricot::fem {

/// Young's modulus and Poisson's ratio of the 3-D law at small strain, for either kinematics:
/// μ = E / (2(1 + ν)), λ = E ν / ((1 + ν)(1 − 2ν)) (λ the 3-D Lamé modulus).
struct YoungPoisson {
  double E = 0;   ///< N/mm (a modulus times the thickness)
  double nu = 0;  ///< in (−1, 0.5)
};

class NeoHookean : public Law {
 public:
  /// Throws InputError (key `law.neo_hookean.mu` / `.lambda`) unless μ > 0 and λ ≥ 0, finite.
  NeoHookean(double mu, double lambda, Kinematics kinematics = Kinematics::plane_stress);
  /// The same law with (E, ν) as its coefficients (names "E", "nu"; ∂P/∂(E, ν) by the chain rule, so
  /// it is not linear in them). Throws InputError (key `law.neo_hookean.E` / `.nu`) unless E > 0 and
  /// −1 < ν < 0.5.
  NeoHookean(YoungPoisson e, Kinematics kinematics = Kinematics::plane_stress);

  std::string name() const override { return "neo_hookean"; }
  std::vector<std::string> coefficient_names() const override;
  Eigen::VectorXd coefficients() const override;
  void set_coefficients(const Eigen::VectorXd& c) override;
  bool linear_in_coefficients() const override { return kinematics_ == Kinematics::plane_strain && !young_poisson_; }
  Kinematics kinematics() const { return kinematics_; }
  /// det F ≤ 0 gives NaN outputs (the solver reports an invalid state).
  void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const override;
  std::unique_ptr<Law> clone() const override { return std::make_unique<NeoHookean>(*this); }

 private:
  double mu_;
  double lambda_;
  Kinematics kinematics_;
  bool young_poisson_ = false;  ///< the coefficients are (E, ν)
  /// ∂P/∂(μ, λ) → ∂P/∂(E, ν) when the coefficients are (E, ν).
  void to_young_poisson(std::vector<Mat2>& dP) const;
  double E_ = 0, nu_ = 0;
};

}  // namespace tricot::fem
