// Compressible Mooney–Rivlin membrane with a volumetric term, in plane stress or plane strain
// (docs/theory.md §5.2): the isochoric invariants Ī1 = J^(−2/3) I1, Ī2 = J^(−4/3) I2 of the 3-D
// C = diag(C₂, C33) and
//   W = Σ C_ij (Ī1 − 3)^i (Ī2 − 3)^j + κ/2 (ln J)².
// Plane strain holds C33 = 1; plane stress finds C33 from S33 = 2 ∂W/∂C33 = 0 (a local Newton), and
// the tangent and ∂P/∂c follow by implicit differentiation of that condition, so they are exact. At
// small strain μ = 2 (C10 + C01) and the bulk modulus is κ. Forces per unit reference length
// (reference thickness 1): the C_ij and κ in N/mm.
#pragma once

#include <vector>

#include "tricot/fem/law.hpp"
#include "tricot/fem/mooney_rivlin.hpp"

namespace tricot::fem {

class CompressibleMooneyRivlin : public Law {
 public:
  /// Throws InputError as MooneyRivlin for the terms (keys `law.mooney_rivlin.terms`, `.values`) and
  /// unless κ > 0, finite (key `law.mooney_rivlin.kappa`).
  CompressibleMooneyRivlin(std::vector<MooneyRivlinTerm> terms, double kappa,
                           Kinematics kinematics = Kinematics::plane_stress);

  std::string name() const override { return "mooney_rivlin_compressible"; }
  /// C<i><j> of each term, then "kappa".
  std::vector<std::string> coefficient_names() const override;
  Eigen::VectorXd coefficients() const override;
  void set_coefficients(const Eigen::VectorXd& c) override;
  /// Plane strain: W is linear in (C_ij, κ) at a fixed C, so P is. Plane stress: C33 moves with them.
  bool linear_in_coefficients() const override { return kinematics_ == Kinematics::plane_strain; }
  Kinematics kinematics() const { return kinematics_; }
  /// det F ≤ 0 gives NaN outputs (the solver reports an invalid state).
  void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const override;
  std::unique_ptr<Law> clone() const override { return std::make_unique<CompressibleMooneyRivlin>(*this); }

  const std::vector<MooneyRivlinTerm>& terms() const { return terms_; }
  double kappa() const { return kappa_; }

 private:
  std::vector<MooneyRivlinTerm> terms_;
  double kappa_;
  Kinematics kinematics_;
};

}  // namespace tricot::fem
