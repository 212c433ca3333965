// Subset matching by inverse-compositional Gauss–Newton on the ZNSSD criterion (docs/theory.md §10;
// Pan, Li & Tong 2013, doi:10.1111/str.12008 for IC-GN in DIC; Gao, Cheng, Yang & Xu 2015,
// doi:10.1016/j.optlaseng.2014.11.018 for the second-order shape function and its composition).
//
// A square subset of N×N pixels around a centre c in the reference image f is compared with the
// current image g through the shape function W(ξ; p), ξ = pixel offset from c:
//     x'(ξ) = c + ξ + (u + ux ξx + uy ξy [+ ½uxx ξx² + uxy ξx ξy + ½uyy ξy²],
//                      v + vx ξx + vy ξy [+ ½vxx ξx² + vxy ξx ξy + ½vyy ξy²]).
// ZNSSD:  C(p) = Σ_ξ [ (f(c+ξ) − f̄)/Δf − (g(x'(ξ)) − ḡ)/Δg ]²,  ZNCC = 1 − C/2.
// IC-GN linearises f rather than g, so the Hessian is computed once per subset; each iteration warps
// the reference subset by Δp and composes W(p) ← W(p) ∘ W(Δp)⁻¹.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>

#include "tricot/core/options.hpp"
#include "tricot/core/types.hpp"
#include "tricot/image/bspline.hpp"

namespace tricot::dic {

/// What became of one point. Only `ok` points carry a measurement.
enum class PointStatus {
  ok,               ///< converged (|Δp| < tolerance) with ZNCC ≥ min_zncc
  max_iterations,   ///< no convergence within max_iterations
  low_correlation,  ///< converged, but ZNCC < min_zncc (or the current subset is blank)
  out_of_image,     ///< the reference or the warped subset leaves the image
  no_texture,       ///< the reference subset is (nearly) uniform: its gray-level spread or gradient is too small
  diverged,         ///< the iteration produced NaN or a degenerate shape (folded subset)
  inconsistent,     ///< converged from a guess, but no good neighbour agrees with it (a look-alike subset)
  not_computed,     ///< propagation never reached the point (disconnected from every seed)
  lost,             ///< sequences: the point was lost in an earlier frame and is no longer tracked
};
/// The lowercase word written in points.csv (`ok`, `max_iterations`, ...).
const char* to_string(PointStatus s);

/// Order of the shape function: first (6 parameters, affine) or second (12 parameters). `automatic`
/// (issue 16): second order only where it pays. Each subset is matched to first order, then refined to
/// second order from there; the second-order match is kept when its six extra parameters lower the
/// residual significantly by the nested-model F-test (extra sum of squares),
///     F = [(SSR₁ − SSR₂)/6] / [SSR₂/(n − 12)] > 3.74 (F₀.₉₉₉(6, ∞) = χ²₆ 99.9 % / 6),  SSR = 2 Δf² (1 − ZNCC),
/// n the subset's pixels (with a Gaussian window, its effective count (Σw)²/Σw²), divided by max(1, 4πσ_p²)
/// when the frames were pre-filtered with σ_p px (the smoothed noise is correlated over that area: counting
/// every pixel as independent made a 2 %-noise translation pass the test at 47 % of the subsets with
/// σ_p = 0.7, docs/validation.md). Elsewhere the first-order match stands, with its lower noise.
enum class ShapeOrder { first = 1, second = 2, automatic = 3 };

/// Shape-function parameters p, in this order:
///   0 u, 1 ux, 2 uy, 3 uxx, 4 uxy, 5 uyy, 6 v, 7 vx, 8 vy, 9 vxx, 10 vxy, 11 vyy.
/// A first-order shape keeps entries 3–5 and 9–11 at zero. u, v in px; gradients dimensionless.
using Shape = Eigen::Matrix<double, 12, 1>;
inline Shape translation(double u, double v) {
  Shape p = Shape::Zero();
  p(0) = u;
  p(6) = v;
  return p;
}
/// The displacement gradient ∇u = [[ux, uy], [vx, vy]] of a shape.
inline Mat2 displacement_gradient(const Shape& p) { return (Mat2() << p(1), p(2), p(7), p(8)).finished(); }
/// The shape moved to another centre: displacement and gradient at offset ξ from the centre (for
/// handing a converged point's shape to its neighbour as a starting guess).
Shape shift_shape(const Shape& p, const Vec2& xi);
/// W(p₁) ∘ W(p₂) and W(p)⁻¹, through Gao's 6×6 matrix representation (exact for first order).
Shape compose(const Shape& p1, const Shape& p2);
Shape inverse(const Shape& p);
/// x'(ξ) − ξ: the displacement the shape gives at offset ξ from the subset centre.
Vec2 warp_displacement(const Shape& p, const Vec2& xi);

/// Settings of one subset match.
struct IcgnOptions {
  int subset_size = 31;                  ///< N, odd, 7–301 px: subset of N×N pixels
  ShapeOrder order = ShapeOrder::first;  ///< first (affine) or second order shape function
  int max_iterations = 50;               ///< 1–1000
  double tolerance = 1e-3;               ///< px, > 0: stop when |Δp| (gradients × N/2) falls below it
  double min_zncc = 0.7;                 ///< 0–1: a converged point below this is `low_correlation`
  /// Fraction of the image's full scale, ≥ 0: a reference subset whose gray-level standard deviation is
  /// below min_texture × full_scale (or whose mean squared gradient is below (min_texture × full_scale / 10)²
  /// per px² along its weakest direction) is `no_texture`.
  double min_texture = 0.005;
  /// px, 0 or 1–1000: the weighting window of the ZNSSD (issue 16). 0 = uniform weights, the plain ZNSSD
  /// above. σ > 0 weights each pixel by w(ξ) = exp(−|ξ|²/(2σ²)) within the N×N box (a Gaussian window, as in
  /// the weighted ZNSSD of Yuan, Huang, Peng, Xiong, Fang & Yuan, Optics and Lasers in Engineering, 2014), so that
  ///     C(p) = Σ_ξ w [ (f − f̄_w)/Δf_w − (g − ḡ_w)/Δg_w ]²,  f̄_w = Σ w f / Σ w,  Δf_w² = Σ w (f − f̄_w)²:
  /// the subset's centre dominates, which narrows the smoothing kernel of a steep displacement gradient for
  /// the same noise (docs/validation.md §3). Sensible σ: N/4 to N/6.
  double weight_sigma = 0;

  /// The config keys of [dic] these options hold (core/options.hpp).
  static auto keys() {
    using O = IcgnOptions;
    return std::tuple{
        option(&O::subset_size, "dic.subset_size",
               "Subset size N: N×N px, odd. Larger is less noisy, smaller follows sharper gradients.", 7, 301),
        option(&O::order, "dic.order",
               "Shape function: first (affine) or second order; auto (the default): second order only where an "
               "F-test\non the residual says it pays (steep gradients), first order elsewhere (less noise).",
               {{ShapeOrder::first, "first"}, {ShapeOrder::second, "second"}, {ShapeOrder::automatic, "auto"}}),
        option(&O::max_iterations, "dic.max_iterations", "IC-GN iterations per subset.", 1, 1000),
        option(&O::tolerance, "dic.tolerance", "px: IC-GN stops when the update moves the subset by less than this.",
               1e-9, 1),
        option(&O::min_zncc, "dic.min_zncc", "A point whose ZNCC is below this is `low_correlation` (not ok).", 0, 1),
        option(&O::min_texture, "dic.min_texture",
               "Fraction of full scale: a subset whose gray-level spread is below it is `no_texture`.", 0, 0.99),
        option(&O::weight_sigma, "dic.weight_sigma",
               "px: Gaussian weighting window of each subset, exp(-r²/2σ²) (0 = uniform weights). N/4–N/6 keeps "
               "the\nnoise of a smaller subset's neighbour but follows steep gradients better (see "
               "docs/validation.md).",
               0, 1000)};
  }
  /// Throws InputError naming the key (`dic.subset_size`, ...) when a field is out of range.
  void validate() const;
};

/// The outcome of one subset match.
struct PointMatch {
  Shape p = Shape::Zero();  ///< from the reference subset centre to the current image
  double zncc = 0;          ///< zero-normalised cross-correlation, 1 = identical
  int iterations = 0;
  PointStatus status = PointStatus::not_computed;
  /// Standard deviations of u and v (px) from image noise, set when the iteration converged (ok or
  /// low_correlation), NaN otherwise. Gauss–Newton's covariance from the match itself (no noise level
  /// to give): the residual r = (f − f̄) − (Δf/Δg)(g − ḡ) has the variance s² = Σ r² / (n − P) per
  /// pixel, Σ r² = 2 Δf² (1 − ZNCC), that of both images' noise; the Hessian H = Σ J Jᵀ (the subset's
  /// gradient energy) holds the reference's noise gradient as well, H = H0 + N, so that
  /// Cov(p) = s² H0⁻¹ H H0⁻¹ (≈ s² H⁻¹ when the texture dominates the noise; icgn.cpp). Checked against
  /// the scatter of matches on noisy synthetic speckle (icgn_test). Ignores the bias of interpolation
  /// and of an unsuited shape function, which are not noise.
  Vec2 sigma{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
};

/// An image ready for correlation: its B-spline interpolant and pixel gradients.
struct Frame {
  image::Image image;  ///< the (pre-filtered) pixels
  image::BSplineImage spline;
  image::Gradient grad;
  /// px: the pre-filter's σ (0 = none). Its smoothing correlates the noise of neighbouring pixels over
  /// about 4πσ² px², which ShapeOrder::automatic's F-test counts (issue 16).
  double prefilter_sigma = 0;
};
/// Pre-filters (Gaussian of `sigma` px, 0 = none) and builds the interpolant and gradients.
Frame prepare_frame(const image::Image& img, double sigma = 0);

/// Matches the subset centred at `centre` in `reference` with `current`, starting from `guess`.
/// Sub-pixel centres are allowed (tracked points); integer centres read pixels directly.
PointMatch icgn(const Frame& reference, const Frame& current, const Vec2& centre, const Shape& guess,
                const IcgnOptions& options);

/// The gray-level standard deviation of the subset and whether it passes the texture test.
bool has_texture(const Frame& reference, const Vec2& centre, const IcgnOptions& options);

}  // namespace tricot::dic
