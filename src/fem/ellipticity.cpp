// Strong ellipticity of a law's tangent (the acoustic tensor), a diagnostic of material stability.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "tricot/fem/law.hpp"

namespace tricot::fem {

namespace {

/// λ_min of sym Q(N), N = (cos t, sin t).
double smallest(const Mat4& A, double t) {
  const Mat2 Q = acoustic_tensor(A, Vec2(std::cos(t), std::sin(t)));
  const double s12 = 0.5 * (Q(0, 1) + Q(1, 0)), m = 0.5 * (Q(0, 0) + Q(1, 1)), d = 0.5 * (Q(0, 0) - Q(1, 1));
  return m - std::hypot(d, s12);
}

}  // namespace

Mat2 acoustic_tensor(const Mat4& A, const Vec2& N) {
  Mat2 Q = Mat2::Zero();
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int l = 0; l < 2; ++l) Q(i, k) += A(2 * i + j, 2 * k + l) * N(j) * N(l);
  return Q;
}

Ellipticity strong_ellipticity(const Mat4& A) {
  constexpr double pi = std::numbers::pi;
  // λ_min(t) is built from harmonics of 2t (Q's entries are quadratic in N): a few minima per half
  // turn. Sample it, then refine every local minimum of the samples by golden section.
  constexpr int kScan = 36;
  constexpr double h = pi / kScan;
  double v[kScan];
  for (int a = 0; a < kScan; ++a) v[a] = smallest(A, a * h);
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  double best = v[0], best_t = 0;
  for (int a = 0; a < kScan; ++a) {
    if (v[a] > v[(a + kScan - 1) % kScan] || v[a] > v[(a + 1) % kScan]) continue;
    double lo = (a - 1) * h, hi = (a + 1) * h;
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = smallest(A, x1), f2 = smallest(A, x2);
    while (hi - lo > 1e-8) {
      if (f1 < f2) {
        hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = smallest(A, x1);
      } else {
        lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = smallest(A, x2);
      }
    }
    const double t = 0.5 * (lo + hi), f = std::min(v[a], smallest(A, t));
    if (f < best) best = f, best_t = f < v[a] ? t : a * h;
  }
  double deg = std::fmod(best_t * 180 / pi, 180.0);
  if (deg < 0) deg += 180;
  return {best, deg};
}

}  // namespace tricot::fem
