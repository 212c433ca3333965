// A material-stability barrier for response-surface identification (docs/theory.md §3, §5; issue 12;
// docs/theory/fabric.md §3.2). The polynomial law has no potential: nothing keeps LM's trial laws
// stable. Where the force–strain Jacobian
//     A(εC, εW) = ∂(F_C, F_W)/∂(εC, εW)
// loses its positive determinant (or an own-direction slope turns negative) at strains the rig's
// fields visit, the membrane localises and an element inverts: the FE fails, and LM, whose best
// points lie next to that boundary, is walled in. The barrier appends to the objective's residuals,
// at every point ε_g of a strain grid,
//     r = w · max(0, m_s − A11)/m_s,   w · max(0, m_s − A22)/m_s,   w · max(0, m_d − det A)/m_d,
// zero for a law stable with margins (m_s, m_d), growing as the law approaches instability. The law
// is linear in its coefficients, so A = Σ_k c_k A_k exactly and ∂r/∂J is exact.
#pragma once

#include <array>
#include <vector>

#include "tricot/core/options.hpp"
#include "tricot/core/types.hpp"
#include "tricot/ident/objective.hpp"

namespace tricot::ident {

struct StabilityBarrierOptions {
  /// The strain grid [Green–Lagrange]: what the rig's fields reach (110 mm campaign: εC ∈ [−0.32,
  /// 1.29], εW ∈ [−0.38, 1.34] at the last step).
  double eC_min = -0.4, eC_max = 1.3, eW_min = -0.4, eW_max = 1.4;
  double step = 0.05;  ///< grid spacing, > 0
  /// m_d [(N/mm)²], > 0: below it det A is penalised. The reference knit's smallest det A over the
  /// grid is 5.2e-3 (at rest: k_C k_W − k_P²), so 2e-3 leaves the truth unpenalised.
  double det_margin = 2e-3;
  /// m_s [N/mm], > 0: below it an own-direction slope is penalised (the knit's smallest: k_W = 0.06).
  double slope_margin = 1e-2;
  double weight = 1;  ///< w ≥ 0; 0 = no barrier (rows of zeros)
  /// m_a [N/mm] ≥ 0: below it the law's strong ellipticity is penalised where the point is taut (one
  /// more row per grid point, after the 3 per point above): a_min, the smallest acoustic eigenvalue
  /// min_N λ_min(sym Q(N)) of the plane-stress law at F = diag(√(1 + 2εC), √(1 + 2εW)) in the material
  /// axes, Q_ik(N) = A_ijkl N_j N_l. The strain-space test above misses it: the corotational frame's
  /// rotation terms make a law that passes it lose ellipticity where its two forces differ much (the
  /// campaign's paper24 at εC −0.3, εW 1.4, the rig's guide end: an element inverts there). The
  /// reference knit's smallest a_min over the default grid's taut points is 0.012 N/mm, so 5e-3
  /// leaves it unpenalised. 0 = no such rows.
  double acoustic_margin = 5e-3;
  /// σ₀ [N/mm] > 0: the ellipticity row is weighted by a C¹ step from 0 at σ_min ≤ 0 to 1 at σ_min ≥ σ₀
  /// (3x² − 2x³, x = σ_min/σ₀), σ_min the smaller
  /// principal value of sym(P Fᵀ) there: only a taut point has stiffness across every direction to
  /// keep (a compressed one loses ellipticity by its compression, which the tension-field membrane
  /// relaxes, docs/theory/fabric.md §8).
  double taut_stress = 1e-3;

  /// The config keys of [stability] these options hold (core/options.hpp); the grid's are no keys.
  static auto keys() {
    using O = StabilityBarrierOptions;
    return std::tuple{
        option(&O::det_margin, "stability.det_margin", "(N/mm)², > 0.", 0, 1e6),
        option(&O::slope_margin, "stability.slope_margin", "N/mm, > 0.", 0, 1e6),
        option(&O::weight, "stability.weight", "w ≥ 0 of each barrier row.", 0, 1e6),
        option(&O::acoustic_margin, "stability.acoustic_margin",
               "N/mm, ≥ 0: also penalise, where the law is taut, a smallest acoustic eigenvalue below it (strong\n"
               "ellipticity of the plane-stress law, which the strain-space rows miss; docs/theory/fabric.md §3.2).\n"
               "0 = off.",
               0, 1e6),
        option(&O::taut_stress, "stability.taut_stress",
               "N/mm, > 0: the ellipticity rows weigh a point fully once its smaller principal stress reaches it,\n"
               "not at all at zero or below (a wrinkled or slack point).",
               0, 1e6)};
  }
  /// Throws InputError naming `stability.<field>`: the grid, the ranges keys() declares and the
  /// open ends that a declared (closed) range cannot say.
  void validate() const;
};

/// The FE objective with the barrier's rows appended (3 per grid point). The law must be a
/// fem::ResponseSurface (InputError naming `law.type` otherwise).
class StabilizedObjective final : public Problem {
 public:
  StabilizedObjective(const Objective& objective, StabilityBarrierOptions options = {});

  const std::vector<Parameter>& parameters() const override { return objective_.parameters(); }
  int residuals() const override { return objective_.residuals() + barrier_rows(); }
  /// The objective's evaluation with the barrier's residuals (and Jacobian rows) appended.
  Evaluation evaluate(const Eigen::VectorXd& J, bool jacobian) const override;
  bool has_exact_jacobian() const override { return objective_.has_exact_jacobian(); }
  /// The objective's variances, the barrier's rows at 1 (they are not measurements).
  Eigen::VectorXd residual_variance() const override;
  /// ½‖barrier(J)‖²: f(J) is the objective's f (≥ 0) plus that.
  double lower_bound(const Eigen::VectorXd& J) const override { return 0.5 * barrier(J).squaredNorm(); }
  bool has_lower_bound() const override { return options_.weight > 0; }
  bool keeps_simulations() const override { return objective_.keeps_simulations(); }

  /// 3 rows per grid point, then one ellipticity row per point when acoustic_margin > 0.
  int barrier_rows() const { return (options_.acoustic_margin > 0 ? 4 : 3) * static_cast<int>(grid_.size()); }
  /// The barrier's residuals at J, and ∂r/∂J when `jacobian` is given.
  Eigen::VectorXd barrier(const Eigen::VectorXd& J, Eigen::MatrixXd* jacobian = nullptr) const;
  /// A(ε_g) of the law at J on every grid point (column-major 2×2 per point).
  std::vector<Mat2> force_jacobians(const Eigen::VectorXd& J) const;
  const std::vector<Vec2>& grid() const { return grid_; }
  const Objective& objective() const { return objective_; }

 private:
  const Objective& objective_;
  StabilityBarrierOptions options_;
  std::vector<Vec2> grid_;                // (εC, εW)
  std::vector<std::vector<Mat2>> basis_;  // basis_[g][i]: A_i at grid point g (law coefficient i)
  // The plane-stress law at grid point g, linear in the coefficients: ∂P/∂F = tangent_[g][0] +
  // Σ_i c_i tangent_[g][i + 1] and P Fᵀ = stress_[g][0] + Σ_i c_i stress_[g][i + 1] ([0]: the fixed
  // shear stiffness alone, the coefficients at 0). Empty when acoustic_margin = 0.
  std::vector<std::vector<Mat4>> tangent_;
  std::vector<std::vector<Mat2>> stress_;
  /// The response surface's coefficients at the parameters J (those not identified at their value).
  Eigen::VectorXd law_coefficients(const Eigen::VectorXd& J) const;
  /// The ellipticity rows' residuals (and their Jacobian rows) at the law's coefficients c.
  void add_ellipticity(const Eigen::VectorXd& c, Eigen::VectorXd& r, Eigen::MatrixXd* jacobian) const;
  Eigen::VectorXd base_;          // the law's coefficients (those not identified stay)
  std::vector<int> coefficient_;  // law coefficient index of each parameter
};

}  // namespace tricot::ident
