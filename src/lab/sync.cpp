#include "tricot/lab/sync.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "tricot/core/error.hpp"
#include "normal_equations.hpp"

namespace tricot::lab {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

void check_series(const std::string& file, const std::string& key, const std::vector<double>& v, std::size_t n) {
  if (v.size() != n)
    throw InputError({file, 0, key}, "wrong length", std::to_string(v.size()),
                     std::to_string(n) + " values, one per time");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i]))
      throw InputError({file, 0, key}, "not a finite number at index " + std::to_string(i), format_number(v[i]),
                       "a finite number");
}

void check_times(const std::string& file, const std::string& key, const std::vector<double>& t) {
  check_series(file, key, t, t.size());
  for (std::size_t i = 1; i < t.size(); ++i)
    if (!(t[i] > t[i - 1]))
      throw InputError({file, 0, key}, "time does not increase at index " + std::to_string(i), format_number(t[i]),
                       "> " + format_number(t[i - 1]));
}

/// f(t) of the piecewise-linear interpolant, t inside [t.front(), t.back()].
double interpolate(const std::vector<double>& t, const std::vector<double>& f, double x) {
  auto it = std::upper_bound(t.begin(), t.end(), x);
  if (it == t.begin()) return f.front();
  if (it == t.end()) return f.back();
  const std::size_t i = static_cast<std::size_t>(it - t.begin());
  const double w = (x - t[i - 1]) / (t[i] - t[i - 1]);
  return (1 - w) * f[i - 1] + w * f[i];
}

/// The minimum of a function of one variable on [a, b] by golden-section search (unimodal there).
template <class F>
double golden_minimum(F&& f, double a, double b, double tolerance) {
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  while (b - a > tolerance) {
    if (fc < fd) {
      b = d, d = c, fd = fc, c = b - g * (b - a), fc = f(c);
    } else {
      a = c, c = d, fc = fd, d = a + g * (b - a), fd = f(d);
    }
  }
  return 0.5 * (a + b);
}

/// Residual sum of squares of the hinge model with its hinge at t0 (docs/theory.md §1: onset fits).
double hinge_rss(const std::vector<double>& t, const std::vector<double>& y, int degree, double t0) {
  NormalEquations ne(degree + 1);
  double phi[6];
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double h = std::max(0.0, t[i] - t0);
    phi[0] = 1;
    for (int j = 1; j <= degree; ++j) phi[j] = phi[j - 1] * h;
    ne.add(phi, y[i]);
  }
  return ne.solve();
}

struct HingeScan {
  std::vector<double> t0, rss;
  double best = nan, best_rss = nan;
};

/// Grid of at most 400 hinge positions over [t.front(), t.back()], then golden-section refinement.
HingeScan hinge_scan(const std::vector<double>& t, const std::vector<double>& y, int degree) {
  HingeScan s;
  const int n = 400;
  const double a = t.front(), b = t.back(), step = (b - a) / n;
  std::size_t ib = 0;
  for (int i = 0; i <= n; ++i) {
    s.t0.push_back(a + i * step);
    s.rss.push_back(hinge_rss(t, y, degree, s.t0.back()));
    if (s.rss.back() < s.rss[ib]) ib = s.rss.size() - 1;
  }
  const double lo = std::max(a, s.t0[ib] - step), hi = std::min(b, s.t0[ib] + step);
  s.best = golden_minimum([&](double t0) { return hinge_rss(t, y, degree, t0); }, lo, hi, 1e-6 * (b - a));
  s.best_rss = hinge_rss(t, y, degree, s.best);
  return s;
}

/// The samples from the start up to where |y − y_rest| first reaches `fraction` of its largest value,
/// y_rest being the mean of the first few samples.
std::size_t onset_window(const std::vector<double>& y, double fraction) {
  const std::size_t m = std::max<std::size_t>(1, std::min<std::size_t>(20, y.size() / 10));
  double y0 = 0;
  for (std::size_t i = 0; i < m; ++i) y0 += y[i] / m;
  double range = 0;
  for (double v : y) range = std::max(range, std::abs(v - y0));
  for (std::size_t i = 0; i < y.size(); ++i)
    if (std::abs(y[i] - y0) >= fraction * range) return i + 1;
  return y.size();
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) ma += a[i] / n, mb += b[i] / n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    sab += (a[i] - ma) * (b[i] - mb), saa += (a[i] - ma) * (a[i] - ma), sbb += (b[i] - mb) * (b[i] - mb);
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0;
}

/// Correlation of the grip motion with the log's cross-head shifted by δ, over the images the log covers:
/// Pearson's r (degree 1), or ±√R² of the least-squares polynomial c ≈ Σ_{j ≤ degree} a_j g^j (the sign of
/// r), which absorbs a smooth nonlinear relation between the field's grip proxy and the cross-head.
double crosshead_correlation(const LoadLog& log, const ImageTimes& images, double delta, int degree) {
  std::vector<double> g, c;
  for (std::size_t k = 0; k < images.time.size(); ++k) {
    const double t = images.time[k] + delta;
    if (t < log.time.front() || t > log.time.back()) continue;
    g.push_back(images.grip[k]);
    c.push_back(interpolate(log.time, log.crosshead, t));
  }
  if (g.size() < 3 || int(g.size()) < degree + 2) return 0;
  const double r = pearson(g, c);
  if (degree <= 1) return r;
  double gmax = 0;
  for (double v : g) gmax = std::max(gmax, std::abs(v));
  if (!(gmax > 0)) return 0;
  NormalEquations ne(degree + 1);
  for (std::size_t k = 0; k < g.size(); ++k) {
    double phi[6], p = 1;
    for (int j = 0; j <= degree; ++j, p *= g[k] / gmax) phi[j] = p;
    ne.add(phi, c[k]);
  }
  const double total = ne.total();
  if (!(total > 0)) return 0;
  return std::copysign(std::sqrt(std::max(0.0, 1 - ne.solve() / total)), r);
}

std::vector<double> head(const std::vector<double>& v, std::size_t n) { return {v.begin(), v.begin() + long(n)}; }

/// The log's median sampling interval.
double log_step(const LoadLog& log) {
  std::vector<double> dt(log.time.size() - 1);
  for (std::size_t i = 1; i < log.time.size(); ++i) dt[i - 1] = log.time[i] - log.time[i - 1];
  std::nth_element(dt.begin(), dt.begin() + long(dt.size() / 2), dt.end());
  return dt[dt.size() / 2];
}

/// The grip motion of a constant-speed test seen in the images: rest until t0, constant speed until
/// t1 (+inf when the images end during the motion), both hinges of the frames (docs/theory.md §1).
struct MotionModel {
  double t0 = nan, t1 = std::numeric_limits<double>::infinity();
  /// Time spent moving by camera time t: clamp(t, t0, t1) − t0.
  double moved(double t) const { return std::clamp(t, t0, t1) - t0; }
};

MotionModel fit_motion(const ImageTimes& images, double fraction) {
  MotionModel m;
  const std::size_t n = images.time.size();
  const std::size_t nw = std::max<std::size_t>(onset_window(images.grip, fraction), 4);
  m.t0 = hinge_onset(head(images.time, nw), head(images.grip, nw), 1);
  if (!(m.t0 > images.time.front()))
    throw InputError({"", 0, "images"}, "the grip already moves in the first image: the onset of motion cannot be seen",
                     "", "images that start at rest, or sync.clock_offset_s");
  // The stop: a hinge in reversed time over the last frames.
  std::vector<double> rt, rg;
  for (std::size_t k = n; k-- > 0;) rt.push_back(-images.time[k]), rg.push_back(images.grip[k]);
  const std::size_t nr = std::max<std::size_t>(onset_window(rg, fraction), 4);
  const double t1 = -hinge_onset(head(rt, std::min(nr, n)), head(rg, std::min(nr, n)), 1);
  const double frame = (images.time.back() - images.time.front()) / double(n - 1);
  if (t1 < images.time.back() - frame && t1 > m.t0) m.t1 = t1;  // at least one frame held
  // Joint refinement over every frame: g = g0 + v·moved(t), linear in (g0, v) for given (t0, t1);
  // alternate golden sections on t0 and t1 around the hinges' values.
  auto rss = [&](const MotionModel& mm) {
    double s0 = 0, s1 = 0, s11 = 0, y0 = 0, y1 = 0, yy = 0;  // normal equations of (g0, v), by hand
    for (std::size_t k = 0; k < n; ++k) {
      const double h = mm.moved(images.time[k]), g = images.grip[k];
      s0 += 1, s1 += h, s11 += h * h, y0 += g, y1 += h * g, yy += g * g;
    }
    const double det = s0 * s11 - s1 * s1;
    if (!(det > 0)) return yy - y0 * y0 / s0;
    const double g0 = (s11 * y0 - s1 * y1) / det, v = (s0 * y1 - s1 * y0) / det;
    return yy - g0 * y0 - v * y1;
  };
  for (int sweep = 0; sweep < 4; ++sweep) {
    MotionModel trial = m;
    m.t0 = golden_minimum(
        [&](double t0) {
          trial.t0 = t0;
          return rss(trial);
        },
        std::max(images.time.front(), m.t0 - frame), std::min(m.t1, m.t0 + frame), 1e-7 * frame);
    if (std::isfinite(m.t1)) {
      trial = m;
      m.t1 = golden_minimum(
          [&](double t1) {
            trial.t1 = t1;
            return rss(trial);
          },
          std::max(m.t0, m.t1 - frame), std::min(images.time.back(), m.t1 + frame), 1e-7 * frame);
    }
  }
  return m;
}

/// Residual sum of squares of F(t) = tare + Σ_{j=1..degree} p_j · moved(t − δ)^j over the log samples
/// at log times in [from, to]; `tss` receives the total sum of squares about the mean.
double force_motion_rss(const LoadLog& log, double from, double to, const MotionModel& m, double delta, int degree,
                        double* tss = nullptr) {
  NormalEquations ne(degree + 1);
  double phi[6];
  for (std::size_t i = 0; i < log.time.size(); ++i) {
    if (log.time[i] < from || log.time[i] > to) continue;
    const double h = m.moved(log.time[i] - delta);
    phi[0] = 1;
    for (int j = 1; j <= degree; ++j) phi[j] = phi[j - 1] * h;
    ne.add(phi, log.force[i]);
  }
  if (tss) *tss = ne.total();
  return ne.solve();
}

}  // namespace

const char* to_string(SyncMethod m) {
  switch (m) {
    case SyncMethod::given: return "given";
    case SyncMethod::crosshead: return "crosshead";
    case SyncMethod::onset: return "onset";
  }
  return "?";
}

std::vector<double> frame_times(int count, double fps, double start_s) {
  if (!(fps > 0) || !std::isfinite(fps))
    throw InputError({"", 0, "images.fps"}, "out of range", format_number(fps), "> 0 images/s");
  if (count < 1) throw InputError({"", 0, "images.count"}, "out of range", std::to_string(count), "≥ 1");
  if (!std::isfinite(start_s)) throw InputError({"", 0, "images.start_s"}, "not a finite time", format_number(start_s));
  std::vector<double> t(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) t[std::size_t(k)] = start_s + k / fps;
  return t;
}

void LoadLog::validate() const {
  if (time.size() < 4)
    throw InputError({source, 0, "log.time"}, "too few samples", std::to_string(time.size()), "at least 4");
  check_times(source, "log.time", time);
  check_series(source, "log.force", force, time.size());
  if (has_crosshead()) check_series(source, "log.crosshead", crosshead, time.size());
}

std::string ImageTimes::name(std::size_t k) const { return k < names.size() ? names[k] : "frame " + std::to_string(k); }

void ImageTimes::validate() const {
  if (time.size() < 3)
    throw InputError({"", 0, "images.time"}, "too few images", std::to_string(time.size()), "at least 3");
  check_times("", "images.time", time);
  check_series("", "images.grip", grip, time.size());
}

void SyncOptions::validate() const {
  auto bad = [](const char* key, double v, const char* expected) {
    throw InputError({"", 0, key}, "out of range", format_number(v), expected);
  };
  if (clock_offset_s && !std::isfinite(*clock_offset_s))
    bad("sync.clock_offset_s", *clock_offset_s, "a finite number of seconds");
  if (tare_N && !std::isfinite(*tare_N)) bad("sync.tare_N", *tare_N, "a finite force");
  if (!(max_offset_s > 0) || !std::isfinite(max_offset_s)) bad("sync.max_offset_s", max_offset_s, "> 0 s");
  if (!(exposure_s >= 0) || !std::isfinite(exposure_s)) bad("sync.exposure_s", exposure_s, "≥ 0 s");
  if (!(onset_fraction > 0 && onset_fraction <= 1)) bad("sync.onset_fraction", onset_fraction, "in (0, 1]");
  if (!(force_degree >= 1 && force_degree <= 5)) bad("sync.force_degree", force_degree, "1 to 5");
  if (!(crosshead_degree >= 1 && crosshead_degree <= 4)) bad("sync.crosshead_degree", crosshead_degree, "1 to 4");
  if (!(tare_margin_s >= 0) || !std::isfinite(tare_margin_s)) bad("sync.tare_margin_s", tare_margin_s, "≥ 0 s");
}

double mean_over(const std::vector<double>& t, const std::vector<double>& f, double a, double b) {
  if (!(b > a)) return interpolate(t, f, a);
  // ∫ of the piecewise-linear interpolant: trapezoids over the samples inside, partial ones at the ends
  double integral = 0, x0 = a, f0 = interpolate(t, f, a);
  for (auto it = std::upper_bound(t.begin(), t.end(), a); it != t.end() && *it < b; ++it) {
    const double f1 = f[std::size_t(it - t.begin())];
    integral += 0.5 * (f0 + f1) * (*it - x0);
    x0 = *it, f0 = f1;
  }
  integral += 0.5 * (f0 + interpolate(t, f, b)) * (b - x0);
  return integral / (b - a);
}

double hinge_onset(const std::vector<double>& t, const std::vector<double>& y, int degree, double* rss) {
  const HingeScan s = hinge_scan(t, y, degree);
  if (rss) *rss = s.best_rss;
  return s.best;
}

SyncResult synchronise(const LoadLog& log, const ImageTimes& images, const SyncOptions& options) {
  options.validate();
  log.validate();
  images.validate();
  SyncResult r;
  r.motion_onset_log_s = r.motion_onset_camera_s = nan;
  double grip_range = 0;
  for (double g : images.grip) grip_range = std::max(grip_range, std::abs(g - images.grip.front()));
  if (!(grip_range > 0))
    throw InputError({"", 0, "images.grip"}, "the grip does not move in the images: nothing to synchronise with");

  // The motion's onset in log time: the cross-head's hinge; else the images' (camera time) + δ.
  std::optional<MotionModel> motion;
  if (log.has_crosshead()) {
    const std::size_t nw = std::max<std::size_t>(onset_window(log.crosshead, options.onset_fraction), 8);
    r.motion_onset_log_s = hinge_onset(head(log.time, nw), head(log.crosshead, nw), 2);
  } else {
    motion = fit_motion(images, options.onset_fraction);
    r.motion_onset_camera_s = motion->t0;
  }

  if (options.clock_offset_s) {
    r.method = SyncMethod::given;
    r.clock_offset_s = *options.clock_offset_s;
    r.message = "clock offset given";
  } else if (log.has_crosshead()) {
    r.method = SyncMethod::crosshead;
    const double step = log_step(log);
    const long n = std::min<long>(std::lround(options.max_offset_s / step), 200000);
    const double h = options.max_offset_s / double(n);
    std::size_t ib = 0;
    for (long i = -n; i <= n; ++i) {
      r.lag_s.push_back(double(i) * h);
      r.correlation.push_back(crosshead_correlation(log, images, r.lag_s.back(), options.crosshead_degree));
      // |r|: a grip measured with the opposite sign to the cross-head correlates at −1
      if (std::abs(r.correlation.back()) > std::abs(r.correlation[ib])) ib = r.correlation.size() - 1;
    }
    const double lo = std::max(-options.max_offset_s, r.lag_s[ib] - h);
    const double hi = std::min(options.max_offset_s, r.lag_s[ib] + h);
    r.clock_offset_s = golden_minimum(
        [&](double d) { return -std::abs(crosshead_correlation(log, images, d, options.crosshead_degree)); }, lo, hi,
        1e-6);
    r.peak_correlation = crosshead_correlation(log, images, r.clock_offset_s, options.crosshead_degree);
    if (ib == 0 || ib + 1 == r.lag_s.size()) r.termination = SyncTermination::at_search_limit;
    r.message = "cross-head correlated with the grip motion";
  } else {
    // Force follows motion: F(t) = tare + P(moved(t − δ)), P a polynomial with P(0) = 0; the force's
    // onset (and stop) then fall on the motion's, and δ minimises the residual.
    r.method = SyncMethod::onset;
    const double step = log_step(log);
    const long n = std::min<long>(std::lround(options.max_offset_s / step), 200000);
    const double h = options.max_offset_s / double(n);
    std::size_t ib = 0;
    std::vector<double> rss;
    const double back = images.time.back();
    for (long i = -n; i <= n; ++i) {
      double tss = 0;
      const double d = double(i) * h;
      r.lag_s.push_back(d);
      // Before the images the grip was at rest (it still is in the first image); after them it holds
      // when the images end on a hold, otherwise the motion there is unknown.
      const double to = std::isfinite(motion->t1) ? log.time.back() : back + d;
      rss.push_back(force_motion_rss(log, log.time.front(), to, *motion, d, options.force_degree, &tss));
      r.correlation.push_back(tss > 0 ? 1 - rss.back() / tss : 0);
      if (rss.back() < rss[ib]) ib = rss.size() - 1;
    }
    // Refinement with a fixed set of samples (the grid's moves samples in and out of the images' span,
    // which makes the residual jump at the grid's own nodes).
    const double d0 = r.lag_s[ib], margin = 2 * h;
    const double from = log.time.front(), to = std::isfinite(motion->t1) ? log.time.back() : back + d0 - margin;
    const double lo = std::max(-options.max_offset_s, d0 - margin);
    const double hi = std::min(options.max_offset_s, d0 + margin);
    r.clock_offset_s = golden_minimum(
        [&](double d) { return force_motion_rss(log, from, to, *motion, d, options.force_degree); }, lo, hi, 1e-6);
    double tss = 0;
    const double best = force_motion_rss(log, from, to, *motion, r.clock_offset_s, options.force_degree, &tss);
    r.peak_correlation = tss > 0 ? 1 - best / tss : 0;
    if (ib == 0 || ib + 1 == r.lag_s.size()) r.termination = SyncTermination::at_search_limit;
    r.message = "onset of force matched with the onset of motion";
  }
  if (motion) r.motion_onset_log_s = motion->t0 + r.clock_offset_s;

  // Tare: the force at rest, before the motion starts (log time).
  if (options.tare_N) {
    r.tare_N = *options.tare_N;
    r.tare_given = true;
  } else {
    double sum = 0;
    for (std::size_t i = 0; i < log.time.size() && log.time[i] < r.motion_onset_log_s - options.tare_margin_s; ++i)
      sum += log.force[i], ++r.tare_samples;
    if (r.tare_samples == 0)
      throw InputError({log.source, 0, "log.force"}, "no force at rest before the motion starts in the log",
                       "onset at " + format_number(r.motion_onset_log_s) + " s",
                       "a log that starts at rest, or sync.tare_N");
    r.tare_N = sum / r.tare_samples;
  }

  // Force at every image, averaged over its exposure.
  const double e = options.exposure_s;
  for (std::size_t k = 0; k < images.time.size(); ++k) {
    const double t = images.time[k] + r.clock_offset_s;
    if (t - 0.5 * e < log.time.front() || t + 0.5 * e > log.time.back())
      throw InputError({log.source, 0, images.name(k)}, "the load-cell log does not cover this image",
                       e > 0 ? fmt::format("log time {:.4f} s ± {:.4g} s of exposure", t, 0.5 * e)
                             : fmt::format("log time {:.4f} s", t),
                       fmt::format("within [{:.4f}, {:.4f}] s", log.time.front(), log.time.back()));
    r.log_time.push_back(t);
    r.force.push_back(mean_over(log.time, log.force, t - 0.5 * e, t + 0.5 * e) - r.tare_N);
    if (log.has_crosshead()) r.crosshead.push_back(mean_over(log.time, log.crosshead, t - 0.5 * e, t + 0.5 * e));
  }
  for (std::size_t k = r.crosshead.size(); k-- > 0;) r.crosshead[k] -= r.crosshead[0];
  return r;
}

std::vector<ForceStep> force_steps(const ImageTimes& images, const SyncResult& sync, const std::vector<double>& grip_mm,
                                   double width_mm) {
  if (!(width_mm > 0) || !std::isfinite(width_mm))
    throw InputError({"", 0, "specimen.width_mm"}, "out of range", format_number(width_mm), "> 0 mm");
  const std::size_t n = images.time.size();
  if (sync.force.size() != n || grip_mm.size() != n)
    throw InputError({"", 0, "images"}, "images, forces and grip displacements differ in number",
                     fmt::format("{}, {} and {}", n, sync.force.size(), grip_mm.size()), "one of each per image");
  std::vector<ForceStep> steps;
  for (std::size_t k = 1; k < n; ++k)
    steps.push_back({int(k), images.time[k] - images.time[0], grip_mm[k], sync.force[k], sync.force[k] / width_mm});
  return steps;
}

std::string SyncResult::brief_report() const {
  std::string s = fmt::format("clock offset {:.4f} s ({}", clock_offset_s, to_string(method));
  if (method == SyncMethod::crosshead) s += fmt::format(", r = {:.6f}", peak_correlation);
  if (method == SyncMethod::onset) s += fmt::format(", R² = {:.6f}", peak_correlation);
  s += "), tare " + format_number(tare_N) + " N";
  s += tare_given ? " (given)" : fmt::format(" from {} samples", tare_samples);
  if (termination == SyncTermination::at_search_limit)
    s += "; at the edge of the search range (raise sync.max_offset_s)";
  return s;
}

}  // namespace tricot::lab
