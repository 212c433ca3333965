#include "tricot/lab/relaxation.hpp"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "normal_equations.hpp"
#include "tricot/core/error.hpp"

namespace tricot::lab {

namespace {

/// r = F∞ + Σ F_i exp(−s / τ_i) − f, parameters x = (F∞, F_1..F_M, ln τ_1..ln τ_M).
template <int M>
struct PronyResidual {
  double s, f;
  template <class T>
  bool operator()(const T* x, T* r) const {
    T v = x[0];
    for (int i = 0; i < M; ++i) v += x[1 + i] * exp(-s * exp(-x[1 + M + i]));
    r[0] = v - f;
    return true;
  }
};

/// Variable projection at fixed τ: the linear least squares in (F∞, F_i). Returns the RSS.
double project(const std::vector<double>& s, const std::vector<double>& f, const std::vector<double>& tau,
               std::size_t stride, std::array<double, 6>* c = nullptr) {
  const int m = static_cast<int>(tau.size()) + 1;
  NormalEquations ne(m);
  double phi[6];
  for (std::size_t k = 0; k < s.size(); k += stride) {
    phi[0] = 1;
    for (std::size_t i = 0; i < tau.size(); ++i) phi[i + 1] = std::exp(-s[k] / tau[i]);
    ne.add(phi, f[k]);
  }
  return ne.solve(c);
}

/// The best τ set of M terms on a log grid (every combination τ_1 < ... < τ_M), by variable projection
/// over at most ~1000 samples.
std::vector<double> grid_start(const std::vector<double>& s, const std::vector<double>& f, int M) {
  const double dt = s[1] - s[0], T = s.back() - s.front();
  const int g = M == 1 ? 80 : M == 2 ? 30 : 16;
  std::vector<double> grid(g);
  const double lo = std::log(std::max(dt, 1e-9)), hi = std::log(3 * T);
  for (int i = 0; i < g; ++i) grid[i] = std::exp(lo + (hi - lo) * i / (g - 1));
  const std::size_t stride = std::max<std::size_t>(1, s.size() / 1000);
  std::vector<double> best, tau(M);
  double best_rss = std::numeric_limits<double>::infinity();
  std::vector<int> idx(M);
  for (int i = 0; i < M; ++i) idx[i] = i;
  for (;;) {
    for (int i = 0; i < M; ++i) tau[i] = grid[idx[i]];
    const double rss = project(s, f, tau, stride);
    if (rss < best_rss) best_rss = rss, best = tau;
    int k = M - 1;  // next combination
    while (k >= 0 && idx[k] == g - M + k) --k;
    if (k < 0) break;
    ++idx[k];
    for (int j = k + 1; j < M; ++j) idx[j] = idx[j - 1] + 1;
  }
  return best;
}

template <int M>
PronyFit fit_terms(const std::vector<double>& s, const std::vector<double>& f) {
  const std::vector<double> tau0 = grid_start(s, f, M);
  std::array<double, 6> c{};
  project(s, f, tau0, 1, &c);
  double x[1 + 2 * M];
  x[0] = c[0];
  for (int i = 0; i < M; ++i) x[1 + i] = c[1 + i], x[1 + M + i] = std::log(tau0[i]);
  ceres::Problem problem;
  for (std::size_t k = 0; k < s.size(); ++k)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PronyResidual<M>, 1, 1 + 2 * M>(new PronyResidual<M>{s[k], f[k]}), nullptr, x);
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = 200;
  o.function_tolerance = 1e-14;
  o.parameter_tolerance = 1e-12;
  o.gradient_tolerance = 1e-14;
  o.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(o, &problem, &summary);

  PronyFit fit;
  fit.converged = summary.IsSolutionUsable();
  fit.relaxed_N = x[0];
  for (int i = 0; i < M; ++i) fit.terms.push_back({x[1 + i], std::exp(x[1 + M + i])});
  std::sort(fit.terms.begin(), fit.terms.end(),
            [](const PronyTerm& a, const PronyTerm& b) { return a.tau_s < b.tau_s; });
  const double n = static_cast<double>(s.size());
  fit.rss = 2 * summary.final_cost;
  fit.rms_N = std::sqrt(fit.rss / n);
  const double k = 2 * M + 1;
  const double lr = std::log(std::max(fit.rss, 1e-300) / n);
  fit.bic = n * lr + k * std::log(n);
  fit.aic = n * lr + 2 * k;
  return fit;
}

void check_series(const std::string& file, const char* key, const std::vector<double>& v, std::size_t n) {
  if (v.size() != n)
    throw InputError({file, 0, key}, "wrong length", std::to_string(v.size()),
                     std::to_string(n) + " values, one per time");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i]))
      throw InputError({file, 0, key}, "not a finite number at index " + std::to_string(i), format_number(v[i]),
                       "a finite number");
}

}  // namespace

void RelaxationOptions::validate() const {
  auto bad = [](const char* key, double v, const char* expected) {
    throw InputError({"", 0, key}, "out of range", format_number(v), expected);
  };
  if (max_terms < 1 || max_terms > 3) bad("relax.max_terms", max_terms, "1 to 3");
  if (!(hold_tolerance > 0 && hold_tolerance <= 0.5)) bad("relax.hold_tolerance", hold_tolerance, "in (0, 0.5]");
  if (!(skip_s >= 0) || !std::isfinite(skip_s)) bad("relax.skip_s", skip_s, "≥ 0 s");
  if (tare_N && !std::isfinite(*tare_N)) bad("relax.tare_N", *tare_N, "a finite force");
  if (!(quasi_static_tolerance > 0) || !std::isfinite(quasi_static_tolerance))
    bad("relax.quasi_static_tolerance", quasi_static_tolerance, "> 0");
}

double PronyFit::force(double s) const {
  double v = relaxed_N;
  for (const auto& t : terms) v += t.amplitude_N * std::exp(-s / t.tau_s);
  return v;
}

double PronyFit::relaxed_ratio() const { return relaxed_N / force(0); }

RelaxationResult fit_relaxation(const std::vector<double>& time, const std::vector<double>& force,
                                const std::vector<double>& crosshead, const RelaxationOptions& options,
                                const std::string& source) {
  options.validate();
  const std::size_t n = time.size();
  check_series(source, "log.time", time, n);
  check_series(source, "log.force", force, n);
  if (!crosshead.empty()) check_series(source, "log.crosshead", crosshead, n);
  for (std::size_t i = 1; i < n; ++i)
    if (!(time[i] > time[i - 1]))
      throw InputError({source, 0, "log.time"}, "time does not increase at index " + std::to_string(i),
                       format_number(time[i]), "> " + format_number(time[i - 1]));

  RelaxationResult r;
  // The hold: the cross-head at its largest travel, else from the force's peak to the end.
  std::size_t first = 0, last = n - 1;
  if (!crosshead.empty()) {
    const double c0 = crosshead.front();
    const double cmax = *std::max_element(crosshead.begin(), crosshead.end());
    const double band = options.hold_tolerance * std::abs(cmax - c0);
    while (first < n && crosshead[first] < cmax - band) ++first;
    last = first;
    while (last + 1 < n && std::abs(crosshead[last + 1] - cmax) <= band) ++last;
    if (options.tare_N) {
      r.tare_N = *options.tare_N;
    } else {
      double sum = 0;
      int count = 0;
      for (std::size_t i = 0; i < n && std::abs(crosshead[i] - c0) <= band; ++i) sum += force[i], ++count;
      if (count > 0) r.tare_N = sum / count, r.tare_estimated = true;
    }
  } else {
    first = static_cast<std::size_t>(std::max_element(force.begin(), force.end()) - force.begin());
    r.tare_N = options.tare_N.value_or(0.0);
  }
  r.hold_start_s = time[first];
  while (first < last && time[first] < r.hold_start_s + options.skip_s) ++first;
  r.hold_first = first, r.hold_last = last, r.hold_end_s = time[last];
  if (last < first + 9)
    throw InputError({source, 0, "log"}, "the hold is too short to fit", std::to_string(last + 1 - first) + " samples",
                     "at least 10 samples where the cross-head holds");

  std::vector<double> s, f;
  for (std::size_t i = first; i <= last; ++i) s.push_back(time[i] - r.hold_start_s), f.push_back(force[i] - r.tare_N);
  for (int m = 1; m <= options.max_terms; ++m) {
    r.fits.push_back(m == 1 ? fit_terms<1>(s, f) : m == 2 ? fit_terms<2>(s, f) : fit_terms<3>(s, f));
    if (!r.fits.back().converged) r.termination = RelaxationTermination::not_converged;
  }
  r.chosen_terms = 1;
  for (int m = 2; m <= options.max_terms; ++m)
    if (r.fits[m - 1].converged && r.fits[m - 1].bic < r.fits[r.chosen_terms - 1].bic) r.chosen_terms = m;
  r.message = r.termination == RelaxationTermination::converged ? "every fit converged" : "some fit did not converge";
  if (crosshead.empty() && !options.tare_N) r.message += "; no cross-head and no tare given: tare taken as 0";
  return r;
}

std::string RelaxationResult::brief_report() const {
  const PronyFit& b = best();
  std::string taus;
  for (const auto& t : b.terms) taus += (taus.empty() ? "" : ", ") + fmt::format("{:.4g} s", t.tau_s);
  std::string s = fmt::format("{} term{}: tau = {}; relaxed/instantaneous = {:.4f}; rms {:.3g} N; BIC", chosen_terms,
                              chosen_terms > 1 ? "s" : "", taus, b.relaxed_ratio(), b.rms_N);
  for (std::size_t m = 0; m < fits.size(); ++m) s += fmt::format(" {:.1f} ({})", fits[m].bic, m + 1);
  return s;
}

QuasiStatic quasi_static(const PronyFit& fit, double duration_s, double tolerance) {
  if (!(duration_s > 0) || !std::isfinite(duration_s))
    throw InputError({"", 0, "relax.duration_s"}, "out of range", format_number(duration_s), "> 0 s");
  if (!(tolerance > 0))
    throw InputError({"", 0, "relax.quasi_static_tolerance"}, "out of range", format_number(tolerance), "> 0");
  auto excess = [&](double T) {
    double e = 0;
    for (const auto& t : fit.terms) e += t.amplitude_N / fit.relaxed_N * (t.tau_s / T) * -std::expm1(-T / t.tau_s);
    return e;
  };
  QuasiStatic q;
  q.duration_s = duration_s;
  q.viscous_excess = excess(duration_s);
  q.quasi_static = q.viscous_excess <= tolerance;
  // excess decreases with T: bisection on ln T
  double lo = 1e-6, hi = 1e12;
  if (excess(lo) <= tolerance) {
    q.min_duration_s = 0;
  } else {
    for (int it = 0; it < 200; ++it) {
      const double mid = std::sqrt(lo * hi);
      (excess(mid) > tolerance ? lo : hi) = mid;
    }
    q.min_duration_s = hi;
  }
  return q;
}

}  // namespace tricot::lab
