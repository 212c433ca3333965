// What the data can tell (docs/theory.md §8, beyond the paper): from the Jacobian S = ∂r/∂J at the optimum,
// which coefficients are pinned down, the least identifiable direction, each test's share of the
// information, and which added test would help most (D- or A-optimal design over candidates).
// Everything is in relative units, S·D with D = diag(|J_k|) (scale_k where J_k = 0), so that
// coefficients of different sizes compare; the information matrix is M = (S D)ᵀ (S D).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "tricot/core/options.hpp"

namespace tricot::ident {

struct IdentifiabilityOptions {
  /// A coefficient is pinned down when its relative standard error √((M⁻¹)_kk)·σ̂ is below this,
  /// (0, ∞). 0.1 = known to 10 %.
  double pinned_relative_error = 0.1;
  /// σ̂² of the residuals (docs/theory.md §8: 2f/(N − n), or 1 when the scales are measurement σ), > 0.
  double sigma2 = 1;

  /// The config key of [identifiability] these options hold (core/options.hpp); sigma2 is the run's.
  static auto keys() {
    using O = IdentifiabilityOptions;
    return std::tuple{option(&O::pinned_relative_error, "identifiability.pinned_relative_error",
                             "A coefficient is pinned down when its relative standard error is below this, > 0.", 0,
                             1e6)};
  }
  /// InputError naming `identifiability.<field>`: the range keys() declares, its open end at 0, sigma2.
  void validate() const;
};

struct IdentifiabilityReport {
  Eigen::VectorXd relative_std_error;  ///< σ̂ √((M⁻¹)_kk) per coefficient; +inf when M is singular along it
  std::vector<bool> pinned;            ///< relative_std_error < pinned_relative_error
  Eigen::VectorXd least_identifiable;  ///< unit eigenvector of M's smallest eigenvalue (largest component > 0)
  double smallest_eigenvalue = 0, largest_eigenvalue = 0;
  /// Per test (the row groups given): its share of tr M, and its share of the information along the
  /// least identifiable direction v (vᵀ M_t v / vᵀ M v); each sums to 1 over the tests.
  std::vector<double> trace_share, weak_direction_share;
};

/// `rows_of_test[t]` lists the rows of S that belong to test t (each row in at most one test).
IdentifiabilityReport identifiability(const Eigen::MatrixXd& S, const Eigen::VectorXd& J, const Eigen::VectorXd& scale,
                                      const std::vector<std::vector<int>>& rows_of_test,
                                      const IdentifiabilityOptions& options = {});

enum class DesignCriterion {
  d_optimal,  ///< maximise det(M + M_c): shrinks the confidence ellipsoid's volume
  a_optimal,  ///< minimise tr((M + M_c)⁻¹): shrinks the mean variance of the coefficients
};
const char* to_string(DesignCriterion c);  ///< "d_optimal", "a_optimal"

/// A test that could be added: its name and its rows of ∂r/∂J at the current J, scaled as the
/// existing data are (the same weights and scales).
struct DesignCandidate {
  std::string name;
  Eigen::MatrixXd S;
};

struct DesignSuggestion {
  int best = -1;              ///< index of the candidate the criterion prefers
  std::vector<double> score;  ///< per candidate: log det(M + M_c) (D) or tr((M + M_c)⁻¹) (A)
  /// Worst relative standard error (σ̂ = 1) now, and with each candidate added.
  double worst_std_error_now = 0;
  std::vector<double> worst_std_error_with;
};

/// Ranks `candidates` by `criterion` (InputError `design.candidates` for none or a column count that
/// is not S's). A singular M is regularised by 1e-12 tr M so that candidates still rank.
DesignSuggestion suggest_test(const Eigen::MatrixXd& S, const Eigen::VectorXd& J, const Eigen::VectorXd& scale,
                              const std::vector<DesignCandidate>& candidates, DesignCriterion criterion);

}  // namespace tricot::ident
