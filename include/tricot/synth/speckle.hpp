// Synthetic speckle images with an analytic motion, for validating DIC (docs/theory.md §10).
// The pattern is a continuous function of reference coordinates X, a sum of Gaussian blobs
//     S(X) = Σ_k w_k exp(−(X − X_k)ᵀ M_k (X − X_k)),   I(X) = background + contrast · (1 − exp(−S(X))),
// round (M_k = I / r_k², w_k = 1) for a painted speckle, elliptical for a knit's stitches,
// so that a deformed image is rendered exactly: pixel x gets the area average of I(φ⁻¹(x')) over the
// pixel (sub-samples × sub-samples points), where φ⁻¹ maps current to reference coordinates. No
// bitmap is ever warped, so the only errors a DIC code sees are its own.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "tricot/core/types.hpp"
#include "tricot/image/bspline.hpp"
#include "tricot/image/image.hpp"

namespace tricot::synth {

/// What the surface looks like.
enum class Texture {
  speckle,  ///< random round blobs: a painted speckle
  knit,     ///< a knit's natural tracers (the paper's, §3.2): a lattice of stitches, each two inclined
            ///< elliptical legs (a V) with jittered position, size and brightness, and random yarn fuzz
};
/// The config word of a texture ("speckle", "knit"), and back (nullopt for an unknown word).
const char* to_string(Texture t);
std::optional<Texture> texture_from_string(std::string_view word);

/// How the speckle looks. Gray levels are fractions of full scale (images have full_scale = 1).
struct SpeckleOptions {
  Texture texture = Texture::speckle;
  double radius = 2.5;         ///< mean blob radius r in px, > 0 (speckle "size" ≈ 2r)
  double radius_spread = 0.3;  ///< relative spread of r, uniform in r·[1 − s, 1 + s], 0–0.9
  double coverage = 0.6;       ///< blobs per unit area × π r², > 0 (how dense the pattern is)
  double background = 0.1;     ///< gray level between blobs, 0–1
  double contrast = 0.8;       ///< gray-level span of a saturated blob, 0–1
  std::uint64_t seed = 1;      ///< random seed of blob positions and sizes
  int subsamples = 4;          ///< per pixel and direction for area integration, 1–16
  /// knit: the stitch pitch across the wales is 4·radius px (2 speckle sizes), along them 3.2·radius;
  /// the wales (columns of stitches) run at this angle from the image's x axis, degrees.
  double wale_angle_deg = 90;

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
  /// I at the nodes (x0 + i·h, y0 + j·h), i < nx, j < ny, of a grid: the same values as intensity()
  /// there (to the order of the sum), found blob by blob over each blob's own ellipse q < 9 rather
  /// than node by node over the neighbouring cells' blobs.
  image::Image intensity_grid(double x0, double y0, double h, int nx, int ny) const;
  /// The smallest length r over which a blob's term falls by e (its shortest semi-axis), px.
  double smallest_radius() const;
  const SpeckleOptions& options() const { return options_; }

 private:
  /// exp(−(a dx² + 2 b dx dy + c dy²)) · weight: round blobs have a = c = 1/r², b = 0.
  struct Blob {
    float x, y, a, b, c, weight;
  };
  void add(const Blob& blob);
  void scatter_round(std::uint64_t count, double radius_scale, double weight_min, std::uint64_t seed);
  void knit_stitches();
  SpeckleOptions options_;
  double x0_, y0_, cell_;
  int nx_, ny_;
  std::vector<std::vector<Blob>> cells_;  ///< blobs binned by cell for fast evaluation
};

/// A pattern tabulated on a grid of step h over a rectangle of the reference plane, with a bicubic
/// B-spline through the grid's values (image::BSplineImage): one lookup of 16 coefficients instead of
/// every neighbouring blob's exponential. h = min(¼ px, 0.45 · smallest_radius()): the B-spline is
/// then within 5e-3 of full scale at worst and 1e-4 RMS on the knit and the round speckle
/// (speckle_test's PatternTable tests). Points off the grid, and every point of a table whose grid would pass
/// kMaxNodes, are the pattern's own intensity().
class PatternTable {
 public:
  /// The table over [x_min, x_max] × [y_min, y_max] (reference px); `pattern` must outlive it.
  PatternTable(const SpecklePattern& pattern, double x_min, double y_min, double x_max, double y_max);
  /// A rectangle of the reference plane, px: its smallest and largest corner.
  struct Box {
    Vec2 lo, hi;
  };
  PatternTable(const SpecklePattern& pattern, const Box& box)
      : PatternTable(pattern, box.lo(0), box.lo(1), box.hi(0), box.hi(1)) {}
  /// I(X): the B-spline where X is on the grid, else pattern.intensity(X).
  double intensity(const Vec2& X) const {
    const double gx = (X(0) - x0_) * inverse_step_, gy = (X(1) - y0_) * inverse_step_;
    if (!spline_.inside(gx, gy)) return pattern_->intensity(X);
    // spline_.value(gx, gy) with the 4 × 4 coefficients combined row by row in 4-wide vectors.
    const double fx = std::floor(gx), fy = std::floor(gy);
    const auto wx = image::bspline_weights(static_cast<float>(gx - fx));
    const auto wy = image::bspline_weights(static_cast<float>(gy - fy));
    const float* c = spline_.origin(static_cast<int>(fx) - 1, static_cast<int>(fy) - 1);
    const std::ptrdiff_t n = spline_.stride();
    using Row = Eigen::Array4f;
    const Row r =
        wy[0] * Row::Map(c) + wy[1] * Row::Map(c + n) + wy[2] * Row::Map(c + 2 * n) + wy[3] * Row::Map(c + 3 * n);
    return (r * Row::Map(wx.data())).sum();
  }
  /// The grid step h, px (0 when the pattern is not tabulated).
  double step() const { return step_; }
  const SpecklePattern& pattern() const { return *pattern_; }

  /// Beyond this many nodes, no table (64 MB of floats, and twice that in doubles while the B-spline
  /// is made; the demo's 110 mm specimen at 0.2 mm/px needs 4.9 million).
  static constexpr double kMaxNodes = 16e6;

 private:
  const SpecklePattern* pattern_;
  double x0_ = 0, y0_ = 0, step_ = 0, inverse_step_ = 0;
  image::BSplineImage spline_;  ///< empty: no table
};

/// Maps a current-image point x to the reference point X = φ⁻¹(x) that is seen there.
using InverseMotion = std::function<Vec2(const Vec2& x)>;

/// Renders a width × height image of the pattern seen through the motion (full_scale = 1).
/// Rendering is parallel over rows (std::thread); `threads` = 0 uses the hardware count.
image::Image render(const SpecklePattern& pattern, int width, int height, const InverseMotion& motion, int threads = 0);
/// The identity motion (the reference image).
inline Vec2 no_motion(const Vec2& x) { return x; }

/// Adds zero-mean Gaussian noise of standard deviation `sigma` (fraction of full scale).
image::Image add_noise(const image::Image& img, double sigma, std::uint64_t seed);

}  // namespace tricot::synth
