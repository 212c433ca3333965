// The data groups of the objective, eq. (1) (docs/theory.md §2): each group g of N_g values has a weight
// w_g and a scale s_g, and contributes the scaled residuals
//     r_i = √(w_g / N_g) · (y_i − y_i^exp) / s_g,   f = ½ Σ r_i².
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace tricot::ident {

enum class GroupKind {
  edge_displacement,  ///< the grip displacement of a test, one value per step
  edge_force,         ///< the grip force of a test, one value per step
  field_u,            ///< u at the points of a test, step-major (all points of step 0, then step 1, …)
  field_v,            ///< v likewise
  field_uv,           ///< u and v in one group with one scale: per step, per point, u then v
};
const char* to_string(GroupKind k);  ///< "edge_displacement", …, "field_uv"

struct DataGroup {
  std::string name;  ///< "<test>/<kind>", e.g. "uniaxial/edge_force"
  GroupKind kind = GroupKind::edge_force;
  int test = -1;       ///< the test's index in the experiment (−1 = none, for analytic problems)
  int offset = 0;      ///< first row of the group in r
  int size = 0;        ///< N_g
  double weight = 1;   ///< w_g
  double scale = 1;    ///< s_g: the measurement σ when given, else the RMS of the group's data
  bool sigma = false;  ///< s_g is a measurement σ (docs/theory.md §8)
};

/// Stacks groups and applies eq. (1).
class ScaledResiduals {
 public:
  /// fixed_weights: each row's factor is √w_g, the weights being absolute (1/unit² of the data): no
  /// division by the group's size or scale, as a published objective Σ_g w_g Σ_i (y_i − y*_i)² has it.
  /// false: eq. (1), √(w_g/N_g)/s_g.
  explicit ScaledResiduals(bool fixed_weights = false) : fixed_(fixed_weights) {}

  /// Appends a group of measured values y_exp with weight w (≥ 0, finite) and measurement σ (0 =
  /// unknown: the scale is then RMS(y_exp)). Throws InputError (key `data.<name>`) for an empty
  /// group, non-finite data, or a zero RMS without σ.
  const DataGroup& add(const std::string& name, GroupKind kind, int test, const Eigen::VectorXd& y_exp,
                       double weight = 1, double sigma = 0);

  /// Appends a group whose every value has its own measurement σ (> 0, finite, one per value): the row
  /// factor is √(w/N)/σ_i, so f stays a χ²/2 and the covariance a real one (docs/theory.md §8). The group's
  /// `scale` reports the RMS of the σ. Throws InputError (key `data.<name>`) as add() and for a σ ≤ 0.
  const DataGroup& add(const std::string& name, GroupKind kind, int test, const Eigen::VectorXd& y_exp, double weight,
                       const Eigen::VectorXd& sigma_per_value);

  const std::vector<DataGroup>& groups() const { return groups_; }
  int size() const { return static_cast<int>(measured_.size()); }
  /// y^exp, stacked in group order.
  const Eigen::VectorXd& measured() const { return measured_; }
  /// √(w_g/N_g)/s_g for every row.
  const Eigen::VectorXd& factors() const { return factor_; }
  /// r = factors ∘ (y − y^exp).
  Eigen::VectorXd residuals(const Eigen::VectorXd& y) const;
  /// ∂y/∂J → ∂r/∂J, in place (rows scaled by factors).
  void scale_rows(Eigen::MatrixXd& dy_dJ) const;
  /// χ² = Σ_i ((y_i − y*_i)/σ_i)² of scaled residuals r (eq. 1 undone: N_g/w_g Σ_{i∈g} r_i² per group,
  /// the row weights left in), over the data's rows; NaN unless every group has a measurement σ. Per
  /// degree of freedom it is 1 for a fit to the noise, and its root is the model-error factor (§8).
  double chi_square(const Eigen::VectorXd& r) const;
  /// Var(r_i) implied by the measurement σ: w_g ω_i/N_g (docs/theory.md §8). Empty unless every group has σ.
  Eigen::VectorXd sigma_variance() const;
  /// Multiplies the weight of each row of group g by ω_i ≥ 0 (one per row; the factor by √ω_i): the
  /// per-step weights of a domain-weighted identification (TestData::step_weight).
  void weight_rows(const DataGroup& g, const Eigen::VectorXd& omega);

 private:
  bool fixed_ = false;
  std::vector<DataGroup> groups_;
  Eigen::VectorXd measured_, factor_;
  Eigen::VectorXd row_weight_;  ///< ω_i, 1 unless weight_rows() set it
};

}  // namespace tricot::ident
