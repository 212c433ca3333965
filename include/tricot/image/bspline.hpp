// Bicubic B-spline interpolation of an image, with gradients (docs/theory.md §10; Unser, Aldroubi & Eden
// 1991, doi:10.1109/78.80892 for the recursive pre-filter; Thévenaz, Blu & Unser 2000,
// doi:10.1109/42.875199 for its boundary conditions).
//
// The image is extended by mirror symmetry and pre-filtered so that the cubic B-spline through the
// coefficients c interpolates the pixels exactly:
//     f(x, y) = Σ_i Σ_j c[j][i] β3(x − i) β3(y − j).
// The interpolant is C², so f and ∇f are continuous — what IC-GN needs for sub-pixel accuracy.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "tricot/image/image.hpp"

namespace tricot::image {

/// The four cubic B-spline weights β3(t + 1 − k), k = 0..3, for the samples i−1, i, i+1, i+2 around a
/// point at i + t, t ∈ [0, 1).
inline std::array<float, 4> bspline_weights(float t) {
  const float t2 = t * t, t3 = t2 * t, s = 1.0f - t;
  return {s * s * s * (1.0f / 6.0f), (3.0f * t3 - 6.0f * t2 + 4.0f) * (1.0f / 6.0f),
          (-3.0f * t3 + 3.0f * t2 + 3.0f * t + 1.0f) * (1.0f / 6.0f), t3 * (1.0f / 6.0f)};
}
/// Their derivatives d/dt.
inline std::array<float, 4> bspline_derivative_weights(float t) {
  const float t2 = t * t, s = 1.0f - t;
  return {-0.5f * s * s, 1.5f * t2 - 2.0f * t, -1.5f * t2 + t + 0.5f, 0.5f * t2};
}

/// Value and gradient of the interpolant at one point.
struct Sample {
  float value = 0, dx = 0, dy = 0;
};

/// The B-spline coefficients of an image and fast evaluation of the interpolant and its gradient.
/// Evaluation is valid for x ∈ [−1, width] and y ∈ [−1, height] (the mirror-extended border); callers
/// check `inside` first. Thread-safe for concurrent reads.
class BSplineImage {
 public:
  BSplineImage() = default;
  explicit BSplineImage(const Image& img);

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return width_ <= 0; }
  /// True when (x, y) lies in the image proper, [0, width−1] × [0, height−1].
  bool inside(double x, double y) const { return x >= 0 && y >= 0 && x <= width_ - 1 && y <= height_ - 1; }

  /// f(x, y).
  float value(double x, double y) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const auto wx = bspline_weights(static_cast<float>(x - fx));
    const auto wy = bspline_weights(static_cast<float>(y - fy));
    const float* c = origin(static_cast<int>(fx) - 1, static_cast<int>(fy) - 1);
    float v = 0;
    for (int j = 0; j < 4; ++j, c += stride_) v += wy[j] * (wx[0] * c[0] + wx[1] * c[1] + wx[2] * c[2] + wx[3] * c[3]);
    return v;
  }

  /// f(x, y) and ∇f(x, y).
  Sample sample(double x, double y) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const float tx = static_cast<float>(x - fx), ty = static_cast<float>(y - fy);
    const auto wx = bspline_weights(tx), wy = bspline_weights(ty);
    const auto dx = bspline_derivative_weights(tx), dy = bspline_derivative_weights(ty);
    const float* c = origin(static_cast<int>(fx) - 1, static_cast<int>(fy) - 1);
    Sample s;
    for (int j = 0; j < 4; ++j, c += stride_) {
      const float rv = wx[0] * c[0] + wx[1] * c[1] + wx[2] * c[2] + wx[3] * c[3];
      const float rd = dx[0] * c[0] + dx[1] * c[1] + dx[2] * c[2] + dx[3] * c[3];
      s.value += wy[j] * rv;
      s.dx += wy[j] * rd;
      s.dy += dy[j] * rv;
    }
    return s;
  }

  /// The coefficient c[y][x] (x, y may reach `pad` outside the image).
  float coefficient(int x, int y) const { return *origin(x, y); }
  /// Pointer to c[y][x]; consecutive x are contiguous, consecutive y are `stride()` apart.
  const float* origin(int x, int y) const {
    return coefficients_.data() + static_cast<std::size_t>(y + pad) * stride_ + (x + pad);
  }
  int stride() const { return stride_; }

  static constexpr int pad = 4;  ///< mirror border kept around the image, in px

 private:
  int width_ = 0, height_ = 0, stride_ = 0;
  std::vector<float> coefficients_;
};

/// ∇f at every pixel centre, from the B-spline: what IC-GN's reference subsets need.
struct Gradient {
  Image dx, dy;
};
Gradient gradient(const BSplineImage& f);

}  // namespace tricot::image
