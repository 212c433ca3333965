// Uncertainty of identified coefficients (docs/theory.md §8, beyond the paper): the Gauss–Newton covariance
// from the Jacobian S = ∂r/∂J at the optimum, and what it says about identifiability.
#pragma once

#include <Eigen/Core>

namespace tricot::ident {

struct Uncertainty {
  /// Cov(J) in the coefficients' units: σ̂² (SᵀS)⁻¹ with σ̂² = 2f/(N − n); or, when every scale is
  /// a measurement σ, (SᵀS)⁻¹ Sᵀ diag(Var r) S (SᵀS)⁻¹, which is σ²(AᵀA)⁻¹ for a linear model.
  Eigen::MatrixXd covariance;
  Eigen::VectorXd std_error;    ///< √diag(covariance); +inf along a direction the data cannot see
  Eigen::MatrixXd correlation;  ///< covariance / (std_error ⊗ std_error); NaN where std_error is inf
  double sigma2 = 1;            ///< the σ̂² used (1 when the variance comes from measurement σ)
  bool from_sigma = false;      ///< the covariance uses the measurement σ, not σ̂²
  /// Singular values of S·D, D = diag(|J_k|) (the scale where J_k = 0): the Jacobian in relative
  /// units, so that they compare across coefficients. Descending.
  Eigen::VectorXd singular_values;
  double condition_number = 0;  ///< σ_max / σ_min of S·D; +inf when rank-deficient
  /// Unit right singular vector of the smallest singular value of S·D: the combination of relative
  /// changes δJ_k/|J_k| that changes the residuals least. Sign: largest component positive.
  Eigen::VectorXd least_identifiable;
  bool full_rank = true;  ///< σ_min > 1e-12 σ_max
};

/// Uncertainty at the optimum J (n) from S (N × n, ∂r/∂J) and r (N). `scale` (n) is used for D
/// where J_k = 0. `variance` (N, optional) = Var(r_i) from measurement σ.
Uncertainty uncertainty(const Eigen::MatrixXd& S, const Eigen::VectorXd& r, const Eigen::VectorXd& J,
                        const Eigen::VectorXd& scale, const Eigen::VectorXd& variance = {});

}  // namespace tricot::ident
