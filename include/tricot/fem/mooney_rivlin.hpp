// Incompressible Mooney–Rivlin membrane in plane stress (docs/theory.md §5, paper eq. 7):
//   W = Σ C_ij (I1 − 3)^i (I2 − 3)^j, any list of (i, j); the paper keeps C10, C20, C21, C03.
// Incompressibility (det C = 1) gives C33 = 1/det C₂ (C₂ the in-plane Cauchy–Green tensor) and the
// pressure is eliminated by σ33 = 0, so W is a function of C₂ alone:
//   I1 = tr C₂ + 1/det C₂,   I2 = tr C₂ / det C₂ + det C₂.
// Stresses are forces per unit reference length (N/mm): the reference thickness is taken as 1, so
// the C_ij are in N/mm.
#pragma once

#include <vector>

#include "tricot/fem/law.hpp"

namespace tricot::fem {

/// One term C (I1 − 3)^i (I2 − 3)^j of the strain energy; named "C<i><j>" (e.g. C10, C03).
struct MooneyRivlinTerm {
  int i = 1;
  int j = 0;
  double C = 0;  ///< N/mm
};

/// Homogeneous states with closed forms (docs/theory.md §5).
enum class HomogeneousMode {
  uniaxial,     ///< λ1 = λ, λ2 = λ3 = λ^(−1/2)
  equibiaxial,  ///< λ1 = λ2 = λ, λ3 = λ^(−2)
  pure_shear,   ///< λ1 = λ, λ2 = 1, λ3 = 1/λ
};

/// The coefficient set of the paper's generated validation case (examples/uniaxial-mooney), chosen
/// here (the paper's Table 1 values are lost): C10 = 0.1, C20 = −0.025, C21 = 0.015, C03 = 0.01 N/mm.
/// Uniaxial: initial modulus 6·C10 = 0.6 N/mm, inflection at λ ≈ 1.44 (slope 0.25 N/mm), stiffening
/// after, P(λ = 2) ≈ 0.45 N/mm; dP/dλ > 0 on λ ∈ [1, 3] in uniaxial, equibiaxial and pure shear.
std::vector<MooneyRivlinTerm> paper_mooney_rivlin_terms();

/// Nominal stress P11 [N/mm] of the homogeneous state `mode` at stretch λ (> 0), docs/theory.md §5 closed
/// forms, e.g. uniaxial P = 2(λ − λ⁻²)(W1 + W2/λ).
double mooney_rivlin_nominal_stress(const std::vector<MooneyRivlinTerm>& terms, HomogeneousMode mode, double lambda);

class MooneyRivlin : public Law {
 public:
  /// Throws InputError for i or j < 0 or > 9, i = j = 0 or a repeated (i, j) (key
  /// `law.mooney_rivlin.terms`), or a non-finite C (key `law.mooney_rivlin.values`): the keys of
  /// `[law.mooney_rivlin]`. An empty list is allowed (a law with no stiffness).
  explicit MooneyRivlin(std::vector<MooneyRivlinTerm> terms);

  std::string name() const override { return "mooney_rivlin"; }
  std::vector<std::string> coefficient_names() const override;
  Eigen::VectorXd coefficients() const override;
  void set_coefficients(const Eigen::VectorXd& c) override;
  bool linear_in_coefficients() const override { return true; }
  /// P = F S₂ with S₂ = 2 ∂W/∂C₂ (the plane-stress-reduced second Piola–Kirchhoff force), A the
  /// exact ∂P/∂F, λ3 = 1/det F, dP_dc the basis stresses. det F ≤ 0 gives NaN outputs (the solver
  /// reports an invalid state).
  void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const override;
  std::unique_ptr<Law> clone() const override { return std::make_unique<MooneyRivlin>(*this); }

  const std::vector<MooneyRivlinTerm>& terms() const { return terms_; }

 private:
  std::vector<MooneyRivlinTerm> terms_;
};

}  // namespace tricot::fem
