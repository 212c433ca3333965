// Synthetic speckle images with an analytic motion, for validating DIC (THEORY.md §10).
// The pattern is a continuous function of reference coordinates X, a sum of Gaussian blobs
//     S(X) = Σ_k exp(−|X − X_k|² / r_k²),   I(X) = background + contrast · (1 − exp(−S(X))),
// so that a deformed image is rendered exactly: pixel x gets the area average of I(φ⁻¹(x')) over the
// pixel (sub-samples × sub-samples points), where φ⁻¹ maps current to reference coordinates. No
// bitmap is ever warped, so the only errors a DIC code sees are its own.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "tricot/core/types.hpp"
#include "tricot/image/image.hpp"

namespace tricot::synth {

/// How the speckle looks. Gray levels are fractions of full scale (images have full_scale = 1).
struct SpeckleOptions {
  double radius = 2.5;        ///< mean blob radius r in px, > 0 (speckle "size" ≈ 2r)
  double radius_spread = 0.3; ///< relative spread of r, uniform in r·[1 − s, 1 + s], 0–0.9
  double coverage = 0.6;      ///< blobs per unit area × π r², > 0 (how dense the pattern is)
  double background = 0.1;    ///< gray level between blobs, 0–1
  double contrast = 0.8;      ///< gray-level span of a saturated blob, 0–1
  std::uint64_t seed = 1;     ///< random seed of blob positions and sizes
  int subsamples = 4;         ///< per pixel and direction for area integration, 1–16

  /// Throws InputError naming the key (`speckle.radius`, ...) when a field is out of range.
  void validate() const;
};

/// A continuous speckle pattern over a rectangle of the reference plane.
class SpecklePattern {
 public:
  /// Blobs are scattered over [x_min, x_max] × [y_min, y_max] (reference px), plus a margin of 3 r.
  SpecklePattern(const SpeckleOptions& options, double x_min, double y_min, double x_max, double y_max);
  /// I(X) at a reference point.
  double intensity(const Vec2& X) const;
  const SpeckleOptions& options() const { return options_; }

 private:
  struct Blob {
    float x, y, inv_r2;
  };
  SpeckleOptions options_;
  double x0_, y0_, cell_;
  int nx_, ny_;
  std::vector<std::vector<Blob>> cells_;  ///< blobs binned by cell for fast evaluation
};

/// Maps a current-image point x to the reference point X = φ⁻¹(x) that is seen there.
using InverseMotion = std::function<Vec2(const Vec2& x)>;

/// Renders a width × height image of the pattern seen through the motion (full_scale = 1).
/// Rendering is parallel over rows (std::thread); `threads` = 0 uses the hardware count.
image::Image render(const SpecklePattern& pattern, int width, int height, const InverseMotion& motion,
                    int threads = 0);
/// The identity motion (the reference image).
inline Vec2 no_motion(const Vec2& x) { return x; }

/// Adds zero-mean Gaussian noise of standard deviation `sigma` (fraction of full scale).
image::Image add_noise(const image::Image& img, double sigma, std::uint64_t seed);

}  // namespace tricot::synth
