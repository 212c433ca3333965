// ZNSSD inverse-compositional Gauss–Newton for one subset (docs/theory.md §10; see icgn.hpp for references).
#include "tricot/dic/icgn.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <vector>

#include "tricot/core/error.hpp"

namespace tricot::dic {

const char* to_string(PointStatus s) {
  switch (s) {
    case PointStatus::ok: return "ok";
    case PointStatus::max_iterations: return "max_iterations";
    case PointStatus::low_correlation: return "low_correlation";
    case PointStatus::out_of_image: return "out_of_image";
    case PointStatus::no_texture: return "no_texture";
    case PointStatus::diverged: return "diverged";
    case PointStatus::inconsistent: return "inconsistent";
    case PointStatus::not_computed: return "not_computed";
    case PointStatus::lost: return "lost";
  }
  return "unknown";
}

void IcgnOptions::validate() const {
  auto bad = [](const char* key, const std::string& got, const std::string& expected,
                const char* problem = "out of range") {
    throw InputError(Location{"", 0, key}, problem, got, expected);
  };
  if (subset_size < 7 || subset_size > 301 || subset_size % 2 == 0)
    bad("dic.subset_size", std::to_string(subset_size), "an odd number of px from 7 to 301",
        subset_size >= 7 && subset_size <= 301 ? "must be odd" : "out of range");
  check_ranges(*this);
  if (!(weight_sigma == 0 || (weight_sigma >= 1 && weight_sigma <= 1000)))
    bad("dic.weight_sigma", std::to_string(weight_sigma), "0 (uniform weights) or 1 to 1000 px");
}

// ---------------------------------------------------------------------------------------------------
// Shape algebra: Gao et al. (2015) represent W(ξ; p) as a 6×6 matrix acting on
// (ξx², ξxξy, ξy², ξx, ξy, 1); composition and inversion become matrix products and inverses.

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

Mat6 warp_matrix(const Shape& p) {
  const double a = p(0), b = 1 + p(1), c = p(2), d = 0.5 * p(3), e = p(4), f = 0.5 * p(5);
  const double g = p(6), s = p(7), t = 1 + p(8), k = 0.5 * p(9), q = p(10), r = 0.5 * p(11);
  Mat6 M;
  M << b * b + 2 * a * d, 2 * b * c + 2 * a * e, c * c + 2 * a * f, 2 * a * b, 2 * a * c, a * a, b * s + a * k + g * d,
      b * t + c * s + a * q + g * e, c * t + a * r + g * f, a * s + g * b, a * t + g * c, a * g, s * s + 2 * g * k,
      2 * s * t + 2 * g * q, t * t + 2 * g * r, 2 * g * s, 2 * g * t, g * g, d, e, f, b, c, a, k, q, r, s, t, g, 0, 0,
      0, 0, 0, 1;
  return M;
}

Shape shape_of(const Mat6& M) {
  Shape p;
  p << M(3, 5), M(3, 3) - 1, M(3, 4), 2 * M(3, 0), M(3, 1), 2 * M(3, 2), M(4, 5), M(4, 3), M(4, 4) - 1, 2 * M(4, 0),
      M(4, 1), 2 * M(4, 2);
  return p;
}

}  // namespace

Shape compose(const Shape& p1, const Shape& p2) { return shape_of(warp_matrix(p1) * warp_matrix(p2)); }
Shape inverse(const Shape& p) { return shape_of(warp_matrix(p).inverse()); }

Vec2 warp_displacement(const Shape& p, const Vec2& xi) {
  const double x = xi(0), y = xi(1);
  return {p(0) + p(1) * x + p(2) * y + 0.5 * p(3) * x * x + p(4) * x * y + 0.5 * p(5) * y * y,
          p(6) + p(7) * x + p(8) * y + 0.5 * p(9) * x * x + p(10) * x * y + 0.5 * p(11) * y * y};
}

Shape shift_shape(const Shape& p, const Vec2& xi) {
  Shape q = p;
  const Vec2 d = warp_displacement(p, xi);
  q(0) = d(0);
  q(1) = p(1) + p(3) * xi(0) + p(4) * xi(1);
  q(2) = p(2) + p(4) * xi(0) + p(5) * xi(1);
  q(6) = d(1);
  q(7) = p(7) + p(9) * xi(0) + p(10) * xi(1);
  q(8) = p(8) + p(10) * xi(0) + p(11) * xi(1);
  return q;
}

Frame prepare_frame(const image::Image& img, double sigma) {
  Frame f;
  f.image = sigma > 0 ? image::gaussian_blur(img, sigma) : img;
  f.spline = image::BSplineImage(f.image);
  f.grad = image::gradient(f.spline);
  f.prefilter_sigma = sigma > 0 ? sigma : 0;
  return f;
}

// ---------------------------------------------------------------------------------------------------
// The reference subset: zero-mean gray levels f − f̄, steepest-descent images J = ∇f · ∂W/∂p, and what
// every iteration reuses (Hessian H = Σ J Jᵀ, Σ J, Σ (f − f̄) J). IC-GN computes all of it once per subset.

namespace {

bool is_integer(double v) { return v == std::floor(v); }

/// The reference subset of one match, in scratch space that each thread reuses (no allocation per point).
template <int NP>
struct Reference {
  using VecP = Eigen::Matrix<double, NP, 1>;
  using MatP = Eigen::Matrix<double, NP, NP>;
  std::vector<float> fc;  ///< f − f̄, n values, row-major over the subset (× w when weighted)
  std::vector<float> J;   ///< NP planes of n values: J[a·n + k] (× w when weighted)
  double df = 0;          ///< √Σ w (f − f̄)²
  /// Gaussian window (IcgnOptions::weight_sigma > 0): w over the subset, row-major, for the size and σ
  /// in w_N, w_sigma; empty for uniform weights. sw = Σ w (n when uniform).
  std::vector<float> w;
  int w_N = 0;
  double w_sigma = 0;
  double sw = 0;
  double sw2 = 0;          ///< Σ w² (n when uniform)
  MatP H2;                 ///< Σ w² J Jᵀ (weighted only: the middle of the covariance sandwich)
  std::vector<float> row;  ///< g − f̄ over the warped subset, row-major (n values)
  float fm = 0;            ///< f̄: subtracted from g too, so that the single-precision row sums stay well conditioned
  MatP H;
  VecP sum_J, sum_fJ;
  Eigen::LDLT<MatP> H_ldlt;
};

template <int NP>
Reference<NP>& reference_scratch() {
  thread_local Reference<NP> r;
  return r;
}

/// The steepest-descent entries of pixel k at offset (x, y): J_a[k] = ∇f · ∂W/∂p_a, stored as NP planes
/// of n values (plane a at J + a·n) so that the per-row sums of the iterations vectorise.
template <int NP>
inline void steepest(float fx, float fy, float x, float y, float* J, std::size_t n, std::size_t k) {
  J[0 * n + k] = fx, J[1 * n + k] = fx * x, J[2 * n + k] = fx * y;
  if constexpr (NP == 6) {
    J[3 * n + k] = fy, J[4 * n + k] = fy * x, J[5 * n + k] = fy * y;
  } else {
    J[3 * n + k] = 0.5f * fx * x * x, J[4 * n + k] = fx * x * y, J[5 * n + k] = 0.5f * fx * y * y;
    J[6 * n + k] = fy, J[7 * n + k] = fy * x, J[8 * n + k] = fy * y;
    J[9 * n + k] = 0.5f * fy * x * x, J[10 * n + k] = fy * x * y, J[11 * n + k] = 0.5f * fy * y * y;
  }
}

/// Reads the reference subset; returns false (with `status`) when it is outside or blank.
template <int NP>
bool read_reference(const Frame& ref, const Vec2& c, const IcgnOptions& o, Reference<NP>& R, PointStatus& status) {
  const int N = o.subset_size, M = N / 2, n = N * N;
  const int W = ref.spline.width(), H = ref.spline.height();
  if (!c.allFinite() || c(0) - M < 0 || c(1) - M < 0 || c(0) + M > W - 1 || c(1) + M > H - 1) {
    status = PointStatus::out_of_image;
    return false;
  }
  R.fc.resize(n);
  R.J.resize(std::size_t(n) * NP);
  R.row.resize(n);
  const bool weighted = o.weight_sigma > 0;
  if (!weighted) {
    R.w.clear();
    R.sw = R.sw2 = n;
  } else if (R.w_N != N || R.w_sigma != o.weight_sigma || R.w.size() != std::size_t(n)) {
    R.w.resize(n);
    const double a = -0.5 / (o.weight_sigma * o.weight_sigma);
    double sw = 0, sw2 = 0;
    for (int dy = -M, k = 0; dy <= M; ++dy)
      for (int dx = -M; dx <= M; ++dx, ++k) {
        const float w = R.w[k] = static_cast<float>(std::exp(a * (dx * dx + dy * dy)));
        sw += w, sw2 += double(w) * w;
      }
    R.w_N = N, R.w_sigma = o.weight_sigma, R.sw = sw, R.sw2 = sw2;
  }
  const bool on_pixels = is_integer(c(0)) && is_integer(c(1));
  double sum = 0;
  int k = 0;
  for (int dy = -M; dy <= M; ++dy)
    for (int dx = -M; dx <= M; ++dx, ++k) {
      float f, fx, fy;
      if (on_pixels) {
        const int x = static_cast<int>(c(0)) + dx, y = static_cast<int>(c(1)) + dy;
        f = ref.image.at(x, y), fx = ref.grad.dx.at(x, y), fy = ref.grad.dy.at(x, y);
      } else {
        const image::Sample v = ref.spline.sample(c(0) + dx, c(1) + dy);
        f = v.value, fx = v.dx, fy = v.dy;
      }
      R.fc[k] = f;
      sum += f;
      steepest<NP>(fx, fy, float(dx), float(dy), R.J.data(), std::size_t(n), std::size_t(k));
    }
  if (weighted) {  // the weighted mean f̄_w
    sum = 0;
    for (int k = 0; k < n; ++k) sum += double(R.w[k]) * R.fc[k];
  }
  const double fm = sum / R.sw;
  R.fm = static_cast<float>(fm);
  double ss = 0;
  if (!weighted) {
    for (float& v : R.fc) {
      v = static_cast<float>(v - fm);
      ss += double(v) * v;
    }
  } else {
    for (int k = 0; k < n; ++k) {
      R.fc[k] = static_cast<float>(R.fc[k] - fm);
      ss += double(R.w[k]) * R.fc[k] * R.fc[k];
    }
  }
  R.df = std::sqrt(ss);
  // H = Σ J Jᵀ, Σ J and Σ (f − f̄) J: dot products of the planes (a small GEMM costs more in set-up)
  const float* fc = R.fc.data();
  if (!weighted) {
    for (int a = 0; a < NP; ++a) {
      const float* Ja = R.J.data() + std::size_t(a) * n;
      float sj = 0, sfj = 0;
#pragma omp simd reduction(+ : sj, sfj)
      for (int k = 0; k < n; ++k) sj += Ja[k], sfj += fc[k] * Ja[k];
      R.sum_J(a) = sj, R.sum_fJ(a) = sfj;
      for (int b = a; b < NP; ++b) {
        const float* Jb = R.J.data() + std::size_t(b) * n;
        float hab = 0;
#pragma omp simd reduction(+ : hab)
        for (int k = 0; k < n; ++k) hab += Ja[k] * Jb[k];
        R.H(a, b) = R.H(b, a) = hab;
      }
    }
  } else {
    // H = Σ w J Jᵀ, Σ w J, Σ w (f − f̄_w) J; then fc and J are stored times w, so that the iterations'
    // sums Σ (w fc) h and Σ h (w J) are the weighted ones with the same loops; H2 = Σ (wJ)(wJ)ᵀ
    const float* w = R.w.data();
    for (int a = 0; a < NP; ++a) {
      const float* Ja = R.J.data() + std::size_t(a) * n;
      float sj = 0, sfj = 0;
#pragma omp simd reduction(+ : sj, sfj)
      for (int k = 0; k < n; ++k) sj += w[k] * Ja[k], sfj += w[k] * fc[k] * Ja[k];
      R.sum_J(a) = sj, R.sum_fJ(a) = sfj;
      for (int b = a; b < NP; ++b) {
        const float* Jb = R.J.data() + std::size_t(b) * n;
        float hab = 0;
#pragma omp simd reduction(+ : hab)
        for (int k = 0; k < n; ++k) hab += w[k] * Ja[k] * Jb[k];
        R.H(a, b) = R.H(b, a) = hab;
      }
    }
    for (int k = 0; k < n; ++k) R.fc[k] *= w[k];
    for (int a = 0; a < NP; ++a)
      for (int k = 0; k < n; ++k) R.J[std::size_t(a) * n + k] *= w[k];
    for (int a = 0; a < NP; ++a)
      for (int b = a; b < NP; ++b) {
        const float* Ja = R.J.data() + std::size_t(a) * n;
        const float* Jb = R.J.data() + std::size_t(b) * n;
        float hab = 0;
#pragma omp simd reduction(+ : hab)
        for (int k = 0; k < n; ++k) hab += Ja[k] * Jb[k];
        R.H2(a, b) = R.H2(b, a) = hab;
      }
  }
  // texture: gray-level spread and the weakest direction of the gradient's second moment
  constexpr int iy = NP == 6 ? 3 : 6;
  const double sxx = R.H(0, 0), syy = R.H(iy, iy), sxy = R.H(0, iy);
  const double level = o.min_texture * ref.image.full_scale;
  const double lambda_min = 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  const double nw = weighted ? R.sw : double(n);  // the weighted count
  if (R.df / std::sqrt(nw) < level || lambda_min / nw < (level / 10) * (level / 10) || R.df == 0) {
    status = PointStatus::no_texture;
    return false;
  }
  R.H_ldlt.compute(R.H);
  if (R.H_ldlt.info() != Eigen::Success || !(R.H_ldlt.rcond() > 1e-12)) {
    status = PointStatus::no_texture;
    return false;
  }
  return true;
}

/// W(p) ∘ W(Δp)⁻¹ for first-order shapes, with 3×3 affine matrices (the 6×6 form is exact but slower).
Shape compose_inverse_affine(const Shape& p, const Shape& dp) {
  Eigen::Matrix3d A, D;
  A << 1 + p(1), p(2), p(0), p(7), 1 + p(8), p(6), 0, 0, 1;
  D << 1 + dp(1), dp(2), dp(0), dp(7), 1 + dp(8), dp(6), 0, 0, 1;
  const Eigen::Matrix3d C = A * D.inverse();
  Shape q = Shape::Zero();
  q(0) = C(0, 2), q(1) = C(0, 0) - 1, q(2) = C(0, 1), q(6) = C(1, 2), q(7) = C(1, 0), q(8) = C(1, 1) - 1;
  return q;
}

/// f(x, y) of the current image's spline (BSplineImage::value, inlined in the hot loop).
inline float spline_value(const float* origin, int stride, double X, double Y) {
  const double fx = std::floor(X), fy = std::floor(Y);
  const auto wx = image::bspline_weights(static_cast<float>(X - fx));
  const auto wy = image::bspline_weights(static_cast<float>(Y - fy));
  const float* c = origin + (static_cast<std::ptrdiff_t>(fy) - 1) * stride + (static_cast<std::ptrdiff_t>(fx) - 1);
  float v = 0;
  for (int j = 0; j < 4; ++j, c += stride) v += wy[j] * (wx[0] * c[0] + wx[1] * c[1] + wx[2] * c[2] + wx[3] * c[3]);
  return v;
}

/// One row of a first-order warped subset: h[i] = g(X0 + ax·x, Y0 + ay·x) − fm at x = i − M, vectorised
/// over the row (issue 16): positions relative to the row's centre pixel in single precision (|x| ≤ a
/// few hundred px, so 1e-5 px), floor by truncation of a shifted value, and the 16 B-spline taps as
/// gathers. Same weights as spline_value.
inline void spline_row(const float* origin, int stride, double X0, double Y0, double ax, double ay, int N, float fm,
                       float* __restrict h) {
  const double bx = std::floor(X0), by = std::floor(Y0);
  const float* const base =
      origin + (static_cast<std::ptrdiff_t>(by) - 1) * stride + (static_cast<std::ptrdiff_t>(bx) - 1);
  const float x0 = static_cast<float>(X0 - bx), y0 = static_cast<float>(Y0 - by);
  const float fax = static_cast<float>(ax), fay = static_cast<float>(ay);
  const int M = N / 2;
  constexpr float kShift = 4096.0f;  // > any offset within a subset: truncation of X + kShift is floor
  constexpr float s6 = 1.0f / 6.0f;
#pragma omp simd
  for (int i = 0; i < N; ++i) {
    const float x = static_cast<float>(i - M);
    const float X = x0 + fax * x, Y = y0 + fay * x;
    const int ix = static_cast<int>(X + kShift) - static_cast<int>(kShift);
    const int iy = static_cast<int>(Y + kShift) - static_cast<int>(kShift);
    const float tx = X - static_cast<float>(ix), ty = Y - static_cast<float>(iy);
    const float tx2 = tx * tx, tx3 = tx2 * tx, sx = 1.0f - tx;
    const float ty2 = ty * ty, ty3 = ty2 * ty, sy = 1.0f - ty;
    const float wx0 = sx * sx * sx * s6, wx1 = (3.0f * tx3 - 6.0f * tx2 + 4.0f) * s6,
                wx2 = (-3.0f * tx3 + 3.0f * tx2 + 3.0f * tx + 1.0f) * s6, wx3 = tx3 * s6;
    const float wy0 = sy * sy * sy * s6, wy1 = (3.0f * ty3 - 6.0f * ty2 + 4.0f) * s6,
                wy2 = (-3.0f * ty3 + 3.0f * ty2 + 3.0f * ty + 1.0f) * s6, wy3 = ty3 * s6;
    const int o = iy * stride + ix;
    const float r0 = wx0 * base[o] + wx1 * base[o + 1] + wx2 * base[o + 2] + wx3 * base[o + 3];
    const float r1 =
        wx0 * base[o + stride] + wx1 * base[o + stride + 1] + wx2 * base[o + stride + 2] + wx3 * base[o + stride + 3];
    const int o2 = o + 2 * stride, o3 = o + 3 * stride;
    const float r2 = wx0 * base[o2] + wx1 * base[o2 + 1] + wx2 * base[o2 + 2] + wx3 * base[o2 + 3];
    const float r3 = wx0 * base[o3] + wx1 * base[o3 + 1] + wx2 * base[o3 + 2] + wx3 * base[o3 + 3];
    h[i] = wy0 * r0 + wy1 * r1 + wy2 * r2 + wy3 * r3 - fm;
  }
}

/// σ of u and v of a converged match (icgn.hpp, PointMatch::sigma). The residual's variance per pixel,
/// s² = Σ r² / (n − P) with Σ r² = 2 Δf² (1 − ZNCC), is the variance of n_f − n_g (both images' noise).
/// The steepest-descent images J hold the reference's noise gradient too, so H = Σ J Jᵀ = H0 + N with
/// N = k σ_f² Σ_ξ blockdiag(ξ ξᵀ, ξ ξᵀ), ξ the shape function's monomials, σ_f² ≈ s²/2 and
/// k = 6√3 − 9 ≈ 1.392 the white-noise power gain of the cubic B-spline derivative at a node. At the
/// converged point Σ J r = 0, so δp = H0⁻¹ Σ J (n_f − n_g) and Cov(p) = s² H0⁻¹ H H0⁻¹.
///
/// With a Gaussian window w (IcgnOptions::weight_sigma), Σ w r² = 2 Δf_w² (1 − ZNCC) gives
/// s² = Σ w r² / (Σw (n − P)/n), N = k σ_f² Σ_ξ w blockdiag(ξ ξᵀ, ξ ξᵀ), and δp = H0⁻¹ Σ w J (n_f − n_g), so
/// Cov(p) = s² H0⁻¹ H2 H0⁻¹ with H2 = Σ w² J Jᵀ (which holds the noise gradient too, like H above).
template <int NP>
Vec2 match_sigma(const Reference<NP>& R, int N, double zncc) {
  using MatP = Eigen::Matrix<double, NP, NP>;
  constexpr int K = NP / 2, iv = K;
  const int M = N / 2, n = N * N;
  const bool weighted = !R.w.empty();
  const double s2 = weighted ? std::max(0.0, 2 * R.df * R.df * (1 - zncc)) / (R.sw * std::max(1, n - NP) / n)
                             : std::max(0.0, 2 * R.df * R.df * (1 - zncc)) / std::max(1, n - NP);
  // Σ w ξ ξᵀ over the subset (w = 1 when uniform), cached per subset size and window
  thread_local int cached_N = 0;
  thread_local double cached_sigma = -1;
  thread_local Eigen::Matrix<double, K, K> Xi;
  const double sigma_w = weighted ? R.w_sigma : 0;
  if (cached_N != N || cached_sigma != sigma_w) {
    Xi.setZero();
    for (int y = -M, k = 0; y <= M; ++y)
      for (int x = -M; x <= M; ++x, ++k) {
        Eigen::Matrix<double, K, 1> xi;
        if constexpr (K == 3) xi << 1, x, y;
        else xi << 1, x, y, 0.5 * x * x, double(x) * y, 0.5 * y * y;
        if (weighted) Xi.noalias() += double(R.w[k]) * xi * xi.transpose();
        else Xi.noalias() += xi * xi.transpose();
      }
    cached_N = N, cached_sigma = sigma_w;
  }
  constexpr double k = 1.3923048454132637;  // 6√3 − 9
  MatP H0 = R.H;
  H0.template topLeftCorner<K, K>() -= k * 0.5 * s2 * Xi;
  H0.template bottomRightCorner<K, K>() -= k * 0.5 * s2 * Xi;
  const Eigen::LDLT<MatP> H0_ldlt(H0);
  MatP cov;
  if (H0_ldlt.info() == Eigen::Success && H0_ldlt.isPositive() && H0_ldlt.rcond() > 1e-12) {
    const MatP A = H0_ldlt.solve(MatP::Identity());
    cov = s2 * A * (weighted ? R.H2 : R.H) * A;
  } else if (!weighted) {  // noise comparable with the texture: no correction
    cov = s2 * R.H_ldlt.solve(MatP::Identity());
  } else {
    const MatP A = R.H_ldlt.solve(MatP::Identity());
    cov = s2 * A * R.H2 * A;
  }
  return {std::sqrt(std::max(0.0, cov(0, 0))), std::sqrt(std::max(0.0, cov(iv, iv)))};
}

template <int NP>
PointMatch icgn_order(const Frame& ref, const Frame& cur, const Vec2& c, const Shape& guess, const IcgnOptions& o) {
  using VecP = Eigen::Matrix<double, NP, 1>;
  PointMatch out;
  Reference<NP>& R = reference_scratch<NP>();
  if (!read_reference<NP>(ref, c, o, R, out.status)) return out;
  const int N = o.subset_size, M = N / 2, n = N * N;
  const double half = M;

  Shape p = guess;
  if constexpr (NP == 6) p(3) = p(4) = p(5) = p(9) = p(10) = p(11) = 0;
  const double W1 = cur.spline.width() - 1, H1 = cur.spline.height() - 1;
  const float* origin = cur.spline.origin(0, 0);
  const int stride = cur.spline.stride();
  auto inside = [&](double X, double Y) { return X >= 0 && Y >= 0 && X <= W1 && Y <= H1; };
  out.status = PointStatus::max_iterations;
  for (int it = 1; it <= o.max_iterations; ++it) {
    out.iterations = it;
    out.p = p;
    // The warped subset must lie in the image: its corners suffice for an affine warp (first order).
    if constexpr (NP == 6) {
      for (int a : {-M, M})
        for (int b : {-M, M}) {
          const Vec2 d = warp_displacement(p, Vec2(a, b));
          const double X = c(0) + a + d(0), Y = c(1) + b + d(1);
          if (!inside(X, Y)) {
            out.status = std::isfinite(X) && std::isfinite(Y) ? PointStatus::out_of_image : PointStatus::diverged;
            return out;
          }
        }
    }
    // One pass over the warped subset: Σh, Σh², Σ(f − f̄)h and Σ h J with h = g − f̄, row by row: first
    // h along the row (the B-spline gathers), then the sums (SIMD; single precision within a row, double
    // across rows).
    // First g − f̄ over the whole warped subset, row by row (the B-spline gathers), then the sums as
    // SIMD dot products over the n pixels (issue 16: one horizontal reduction per sum, not per row).
    float* const h0 = R.row.data();
    const float* const J = R.J.data();
    const float* const fc = R.fc.data();
    const float fm = R.fm;  // locals: the compiler cannot keep thread-local members in registers across stores to h
    const float* const weights = R.w.empty() ? nullptr : R.w.data();
    const double sw = R.sw;
    for (int y = -M, row = 0; y <= M; ++y, row += N) {
      float* const h = h0 + row;
      // first-order part of the warp along the row: X = X0 + (1 + ux)·x, Y = Y0 + vx·x
      const double X0 = c(0) + p(0) + p(2) * y, Y0 = c(1) + y + p(6) + p(8) * y;
      const double ax = 1 + p(1), ay = p(7);
      if constexpr (NP == 6) {
        spline_row(origin, stride, X0, Y0, ax, ay, N, fm, h);
      } else {
        for (int i = 0; i < N; ++i) {
          const int x = i - M;
          const double X = X0 + ax * x + 0.5 * p(3) * x * x + p(4) * x * y + 0.5 * p(5) * y * y;
          const double Y = Y0 + ay * x + 0.5 * p(9) * x * x + p(10) * x * y + 0.5 * p(11) * y * y;
          if (!inside(X, Y)) {
            out.status = std::isfinite(X) && std::isfinite(Y) ? PointStatus::out_of_image : PointStatus::diverged;
            return out;
          }
          h[i] = spline_value(origin, stride, X, Y) - fm;
        }
      }
    }
    const float* const h = h0;
    float rg = 0, rgg = 0, rfg = 0;
    if (weights == nullptr) {
#pragma omp simd reduction(+ : rg, rgg, rfg)
      for (int k = 0; k < n; ++k) rg += h[k], rgg += h[k] * h[k], rfg += fc[k] * h[k];
    } else {  // fc and J are stored times w already
#pragma omp simd reduction(+ : rg, rgg, rfg)
      for (int k = 0; k < n; ++k) {
        const float wh = weights[k] * h[k];
        rg += wh, rgg += wh * h[k], rfg += fc[k] * h[k];
      }
    }
    const double sg = rg, sgg = rgg, sfg = rfg;
    VecP sgJ;
    for (int a = 0; a < NP; ++a) {
      const float* Ja = J + std::size_t(a) * n;
      float sa = 0;
#pragma omp simd reduction(+ : sa)
      for (int k = 0; k < n; ++k) sa += h[k] * Ja[k];
      sgJ(a) = sa;
    }
    const double hm = sg / sw;  // ḡ − f̄ (weighted means when weighted)
    const double dg = std::sqrt(std::max(0.0, sgg - sg * hm));
    if (!(dg > 1e-6 * R.df)) {  // the warped subset is blank
      out.status = PointStatus::low_correlation;
      out.zncc = 0;
      return out;
    }
    out.zncc = sfg / (R.df * dg);  // Σ(f − f̄)(g − ḡ) = Σ(f − f̄)h since Σ(f − f̄) = 0
    // ∇C ∝ Σ [(f − f̄) − (Δf/Δg)(g − ḡ)] J, with Σ (g − ḡ) J = Σ h J − (ḡ − f̄) Σ J
    const VecP b = R.sum_fJ - (R.df / dg) * (sgJ - hm * R.sum_J);
    const VecP dp = -R.H_ldlt.solve(b);
    Shape dP = Shape::Zero();
    if constexpr (NP == 6) {
      dP(0) = dp(0), dP(1) = dp(1), dP(2) = dp(2), dP(6) = dp(3), dP(7) = dp(4), dP(8) = dp(5);
    } else {
      dP = dp;
    }
    p = NP == 6 ? compose_inverse_affine(p, dP) : shape_of(warp_matrix(p) * warp_matrix(dP).inverse());
    out.p = p;
    if (!p.allFinite() || (Mat2::Identity() + displacement_gradient(p)).determinant() < 0.05) {
      out.status = PointStatus::diverged;
      return out;
    }
    double norm2 =
        dP(0) * dP(0) + dP(6) * dP(6) + half * half * (dP(1) * dP(1) + dP(2) * dP(2) + dP(7) * dP(7) + dP(8) * dP(8));
    if constexpr (NP == 12)
      norm2 += 0.25 * half * half * half * half *
               (dP.template segment<3>(3).squaredNorm() + dP.template segment<3>(9).squaredNorm());
    if (norm2 < o.tolerance * o.tolerance) {
      out.status = out.zncc >= o.min_zncc ? PointStatus::ok : PointStatus::low_correlation;
      out.sigma = match_sigma<NP>(R, N, out.zncc);
      return out;
    }
  }
  return out;
}

}  // namespace

PointMatch icgn(const Frame& reference, const Frame& current, const Vec2& centre, const Shape& guess,
                const IcgnOptions& options) {
  options.validate();
  if (options.order == ShapeOrder::first) return icgn_order<6>(reference, current, centre, guess, options);
  if (options.order == ShapeOrder::second) return icgn_order<12>(reference, current, centre, guess, options);
  // automatic: first order, then second order from it, kept when the F-test says it pays (icgn.hpp)
  const PointMatch first = icgn_order<6>(reference, current, centre, guess, options);
  if (first.status != PointStatus::ok && first.status != PointStatus::low_correlation) return first;
  PointMatch second = icgn_order<12>(reference, current, centre, first.p, options);
  second.iterations += first.iterations;
  if (second.status != PointStatus::ok && second.status != PointStatus::low_correlation) return first;
  const Reference<12>& R = reference_scratch<12>();
  const double sp = reference.prefilter_sigma;
  const double n = (R.w.empty() ? double(options.subset_size) * options.subset_size : R.sw * R.sw / R.sw2) /
                   std::max(1.0, 4 * std::numbers::pi * sp * sp);
  // F₀.₉₉₉(6, ν) → χ²₆ quantile / 6 = 22.458/6 = 3.743 as ν → ∞; used for every ν (ν ≥ 37 here, where the
  // exact quantile is higher, so small subsets test at a level somewhat above 0.1 %). The pixels'
  // residuals are not quite independent (interpolation), so the level is nominal anyway.
  const double nu = std::max(1.0, n - 12);
  constexpr double f_crit = 22.4577 / 6;
  const double ssr1 = std::max(0.0, 1 - first.zncc), ssr2 = std::max(1e-300, 1 - second.zncc);
  const double F = (ssr1 - ssr2) / 6 / (ssr2 / nu);
  if (F > f_crit) return second;
  PointMatch out = first;
  out.iterations = second.iterations;
  return out;
}

bool has_texture(const Frame& reference, const Vec2& centre, const IcgnOptions& options) {
  PointStatus s;
  return read_reference<6>(reference, centre, options, reference_scratch<6>(), s);
}

}  // namespace tricot::dic
