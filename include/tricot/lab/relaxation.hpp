// Relaxation tests (paper §3.1.1: the knit's characteristic relaxation time is about 6 min). A strip
// is pulled to a displacement that is then held; the force relaxes. The hold's force is fitted by a
// Prony series of one to three exponentials,
//     F(s) = F∞ + Σ_{i=1..m} F_i exp(−s / τ_i),     s = time since the hold began,
// first by variable projection (F∞, F_i are linear for given τ: a grid of τ on a log scale), then
// polished by Ceres (Levenberg–Marquardt in F∞, F_i, ln τ_i). The number of terms is chosen by the
// Schwarz criterion BIC = n ln(RSS/n) + k ln n (k = 2m + 1): a term is kept only when it explains
// more than noise. Whether a loading of duration T is quasi-static follows from the fitted series
// (Boltzmann superposition, constant rate over T): the force then exceeds the relaxed one by
//     excess(T) = Σ_i (F_i / F∞) (τ_i / T) (1 − exp(−T / τ_i)),
// and the test is quasi-static when the excess is below a tolerance.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace tricot::lab {

struct RelaxationOptions {
  int max_terms = 3;  ///< Prony terms tried, 1–3
  /// The hold: the cross-head stays within this fraction of its travel of its largest value, (0, 0.5].
  double hold_tolerance = 0.002;
  /// Left out of the fit after the hold begins (the end of the ramp), s, ≥ 0.
  double skip_s = 0;
  /// Force at rest, N; when unset it is the mean force before the ramp (needs the cross-head).
  std::optional<double> tare_N;
  /// quasi_static(): largest viscous excess over the relaxed force, > 0.
  double quasi_static_tolerance = 0.05;

  /// Throws InputError naming `relax.<field>` when out of range.
  void validate() const;
};

struct PronyTerm {
  double amplitude_N = 0;  ///< F_i
  double tau_s = 0;        ///< τ_i
};

/// One Prony series fitted to the hold.
struct PronyFit {
  std::vector<PronyTerm> terms;  ///< by increasing τ
  double relaxed_N = 0;          ///< F∞
  double rss = 0;                ///< residual sum of squares, N²
  double rms_N = 0;              ///< √(rss / n)
  double bic = 0, aic = 0;       ///< n ln(rss/n) + k ln n, n ln(rss/n) + 2k
  bool converged = false;        ///< Ceres reported a usable solution

  /// F(s) of the series, s ≥ 0 since the hold began.
  double force(double s) const;
  /// F∞ / F(0): the relaxed over the instantaneous force of the hold.
  double relaxed_ratio() const;
};

enum class RelaxationTermination {
  converged,      ///< every fit converged
  not_converged,  ///< some fit did not converge (its `converged` is false); the others stand
};

struct RelaxationResult {
  RelaxationTermination termination = RelaxationTermination::converged;
  double tare_N = 0;
  bool tare_estimated = false;
  double hold_start_s = 0, hold_end_s = 0;    ///< times in the log
  std::size_t hold_first = 0, hold_last = 0;  ///< sample indices (inclusive) of the fitted hold
  std::vector<PronyFit> fits;                 ///< fits[m − 1] has m terms
  int chosen_terms = 1;                       ///< the fit with the lowest BIC
  std::string message;

  const PronyFit& best() const { return fits.at(std::size_t(chosen_terms - 1)); }
  /// "2 terms: τ = 35.2 s, 361 s; F∞/F0 = 0.612; rms 0.10 N (BIC −1234 vs −987 for 1 term)".
  std::string brief_report() const;
};

/// Finds the hold and fits 1..max_terms Prony series. `crosshead` may be empty: the hold then begins
/// at the force's peak and lasts to the end, and the tare must be given (or it is taken as 0). Throws
/// InputError for series of different lengths, non-finite values, times that do not increase, or a
/// hold shorter than 10 samples.
RelaxationResult fit_relaxation(const std::vector<double>& time, const std::vector<double>& force,
                                const std::vector<double>& crosshead, const RelaxationOptions& options = {},
                                const std::string& source = {});

/// Whether a monotonic test of duration T at constant rate is quasi-static against a fitted series.
struct QuasiStatic {
  double duration_s = 0;
  double viscous_excess = 0;  ///< excess(T) of the header, fraction of the relaxed force
  bool quasi_static = false;  ///< viscous_excess ≤ tolerance
  double min_duration_s = 0;  ///< the shortest T with excess(T) ≤ tolerance
};
QuasiStatic quasi_static(const PronyFit& fit, double duration_s, double tolerance = 0.05);

}  // namespace tricot::lab
