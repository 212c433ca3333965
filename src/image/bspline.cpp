// Cubic B-spline pre-filter (Unser's recursive filter) and gradients at pixel centres.
#include "tricot/image/bspline.hpp"

#include <cmath>

#include "mirror.hpp"

namespace tricot::image {

namespace {

/// The pole of the cubic B-spline pre-filter, z1 = √3 − 2 (Unser 1991).
const double z1 = std::sqrt(3.0) - 2.0;

/// In-place pre-filter of one line of n samples, spaced `step` apart, with mirror boundaries
/// (Thévenaz, Blu & Unser 2000, Box 2): turns samples into interpolating coefficients.
void prefilter_line(double* s, int n) {
  if (n < 2) return;
  const double gain = (1 - z1) * (1 - 1 / z1);  // = 6
  for (int k = 0; k < n; ++k) s[k] *= gain;
  // causal initialisation: Σ z^k s[k], truncated where z^k falls below double precision
  const int horizon = std::min(n, static_cast<int>(std::ceil(std::log(1e-16) / std::log(std::abs(z1)))));
  double zk = 1, c0 = 0;
  for (int k = 0; k < horizon; ++k, zk *= z1) c0 += zk * s[k];
  s[0] = c0;
  for (int k = 1; k < n; ++k) s[k] += z1 * s[k - 1];
  // anti-causal initialisation for mirror boundaries
  s[n - 1] = (z1 / (z1 * z1 - 1)) * (s[n - 1] + z1 * s[n - 2]);
  for (int k = n - 2; k >= 0; --k) s[k] = z1 * (s[k + 1] - s[k]);
}

}  // namespace

BSplineImage::BSplineImage(const Image& img) : width_(img.width), height_(img.height) {
  if (img.empty()) return;
  // Mirror-extend by `pad` on every side, then pre-filter the extended image; the spline through the
  // coefficients interpolates the pixels of the image proper exactly.
  const int W = width_ + 2 * pad, H = height_ + 2 * pad;
  stride_ = W;
  std::vector<double> c(static_cast<std::size_t>(W) * H);
  for (int y = 0; y < H; ++y) {
    const int sy = detail::mirror(y - pad, height_);
    for (int x = 0; x < W; ++x) c[std::size_t(y) * W + x] = img.at(detail::mirror(x - pad, width_), sy);
  }
  for (int y = 0; y < H; ++y) prefilter_line(&c[std::size_t(y) * W], W);
  std::vector<double> col(H);
  for (int x = 0; x < W; ++x) {
    for (int y = 0; y < H; ++y) col[y] = c[std::size_t(y) * W + x];
    prefilter_line(col.data(), H);
    for (int y = 0; y < H; ++y) c[std::size_t(y) * W + x] = col[y];
  }
  coefficients_.assign(c.begin(), c.end());
}

Gradient gradient(const BSplineImage& f) {
  // At a node the derivative weights are (−1/2, 0, 1/2) and the value weights (1/6, 2/3, 1/6).
  Gradient g{Image(f.width(), f.height()), Image(f.width(), f.height())};
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      const float* c = f.origin(x, y);
      const int s = f.stride();
      auto smooth_x = [&](const float* p) { return (p[-1] + 4.0f * p[0] + p[1]) * (1.0f / 6.0f); };
      auto diff_x = [&](const float* p) { return 0.5f * (p[1] - p[-1]); };
      g.dx.at(x, y) = (diff_x(c - s) + 4.0f * diff_x(c) + diff_x(c + s)) * (1.0f / 6.0f);
      g.dy.at(x, y) = 0.5f * (smooth_x(c + s) - smooth_x(c - s));
    }
  return g;
}

}  // namespace tricot::image
