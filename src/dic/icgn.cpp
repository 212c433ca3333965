// ZNSSD inverse-compositional Gauss–Newton for one subset (THEORY.md §10; see icgn.hpp for references).
#include "tricot/dic/icgn.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
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
    case PointStatus::not_computed: return "not_computed";
    case PointStatus::lost: return "lost";
  }
  return "unknown";
}

void IcgnOptions::validate() const {
  auto bad = [](const char* key, const std::string& got, const std::string& expected) {
    throw InputError(Location{"", 0, key}, "out of range", got, expected);
  };
  if (subset_size < 7 || subset_size > 301 || subset_size % 2 == 0)
    bad("dic.subset_size", std::to_string(subset_size), "an odd number of px from 7 to 301");
  if (max_iterations < 1 || max_iterations > 1000) bad("dic.max_iterations", std::to_string(max_iterations), "1 to 1000");
  if (!(tolerance > 0) || !std::isfinite(tolerance)) bad("dic.tolerance", std::to_string(tolerance), "> 0 px");
  if (!(min_zncc >= 0 && min_zncc <= 1)) bad("dic.min_zncc", std::to_string(min_zncc), "0 to 1");
  if (!(min_texture >= 0 && min_texture < 1)) bad("dic.min_texture", std::to_string(min_texture), "0 to 1");
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
  M << b * b + 2 * a * d, 2 * b * c + 2 * a * e, c * c + 2 * a * f, 2 * a * b, 2 * a * c, a * a,
      b * s + a * k + g * d, b * t + c * s + a * q + g * e, c * t + a * r + g * f, a * s + g * b, a * t + g * c, a * g,
      s * s + 2 * g * k, 2 * s * t + 2 * g * q, t * t + 2 * g * r, 2 * g * s, 2 * g * t, g * g,
      d, e, f, b, c, a,
      k, q, r, s, t, g,
      0, 0, 0, 0, 0, 1;
  return M;
}

Shape shape_of(const Mat6& M) {
  Shape p;
  p << M(3, 5), M(3, 3) - 1, M(3, 4), 2 * M(3, 0), M(3, 1), 2 * M(3, 2),
       M(4, 5), M(4, 3), M(4, 4) - 1, 2 * M(4, 0), M(4, 1), 2 * M(4, 2);
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
  return f;
}

// ---------------------------------------------------------------------------------------------------
// The reference subset: offsets, zero-mean gray levels, steepest-descent images J = ∇f · ∂W/∂p.

namespace {

/// Scratch space reused by every call on one thread.
struct Scratch {
  std::vector<float> xi_x, xi_y, fc, fx, fy, g;
};
thread_local Scratch scratch;

bool is_integer(double v) { return v == std::floor(v); }

/// Reads the reference subset; returns false (with `status`) when it is outside or blank.
bool read_reference(const Frame& ref, const Vec2& c, const IcgnOptions& o, double& df, PointStatus& status) {
  const int N = o.subset_size, M = N / 2, n = N * N;
  const int W = ref.spline.width(), H = ref.spline.height();
  if (c(0) - M < 0 || c(1) - M < 0 || c(0) + M > W - 1 || c(1) + M > H - 1) {
    status = PointStatus::out_of_image;
    return false;
  }
  Scratch& s = scratch;
  s.xi_x.resize(n), s.xi_y.resize(n), s.fc.resize(n), s.fx.resize(n), s.fy.resize(n), s.g.resize(n);
  const bool on_pixels = is_integer(c(0)) && is_integer(c(1));
  double sum = 0;
  int i = 0;
  for (int dy = -M; dy <= M; ++dy)
    for (int dx = -M; dx <= M; ++dx, ++i) {
      s.xi_x[i] = static_cast<float>(dx);
      s.xi_y[i] = static_cast<float>(dy);
      if (on_pixels) {
        const int x = static_cast<int>(c(0)) + dx, y = static_cast<int>(c(1)) + dy;
        s.fc[i] = ref.image.at(x, y);
        s.fx[i] = ref.grad.dx.at(x, y);
        s.fy[i] = ref.grad.dy.at(x, y);
      } else {
        const image::Sample v = ref.spline.sample(c(0) + dx, c(1) + dy);
        s.fc[i] = v.value, s.fx[i] = v.dx, s.fy[i] = v.dy;
      }
      sum += s.fc[i];
    }
  const double fm = sum / n;
  double ss = 0, sxx = 0, sxy = 0, syy = 0;
  for (int k = 0; k < n; ++k) {
    s.fc[k] = static_cast<float>(s.fc[k] - fm);
    ss += double(s.fc[k]) * s.fc[k];
    sxx += double(s.fx[k]) * s.fx[k], sxy += double(s.fx[k]) * s.fy[k], syy += double(s.fy[k]) * s.fy[k];
  }
  df = std::sqrt(ss);
  const double level = o.min_texture * ref.image.full_scale;
  const double lambda_min = 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  if (df / std::sqrt(double(n)) < level || lambda_min / n < (level / 10) * (level / 10) || df == 0) {
    status = PointStatus::no_texture;
    return false;
  }
  return true;
}

template <int NP>
PointMatch icgn_order(const Frame& ref, const Frame& cur, const Vec2& c, const Shape& guess, const IcgnOptions& o) {
  using VecP = Eigen::Matrix<double, NP, 1>;
  using MatP = Eigen::Matrix<double, NP, NP>;
  PointMatch out;
  double df = 0;
  if (!read_reference(ref, c, o, df, out.status)) return out;
  const Scratch& s = scratch;
  const int n = o.subset_size * o.subset_size;
  const double half = o.subset_size / 2;

  // Hessian of the linearised ZNSSD, once per subset (the point of the inverse-compositional scheme).
  MatP H = MatP::Zero();
  Eigen::Matrix<double, NP, 1> Ji;
  auto steepest = [&](int k) {
    const double fx = s.fx[k], fy = s.fy[k], x = s.xi_x[k], y = s.xi_y[k];
    if constexpr (NP == 6) {
      Ji << fx, fx * x, fx * y, fy, fy * x, fy * y;
    } else {
      Ji << fx, fx * x, fx * y, 0.5 * fx * x * x, fx * x * y, 0.5 * fx * y * y, fy, fy * x, fy * y, 0.5 * fy * x * x,
          fy * x * y, 0.5 * fy * y * y;
    }
  };
  for (int k = 0; k < n; ++k) {
    steepest(k);
    H.template selfadjointView<Eigen::Lower>().rankUpdate(Ji);
  }
  H = H.template selfadjointView<Eigen::Lower>();
  const Eigen::LDLT<MatP> Hinv(H);
  if (Hinv.info() != Eigen::Success || !(Hinv.rcond() > 1e-12)) {
    out.status = PointStatus::no_texture;
    return out;
  }

  Shape p = guess;
  if constexpr (NP == 6) p(3) = p(4) = p(5) = p(9) = p(10) = p(11) = 0;
  const double W1 = cur.spline.width() - 1, H1 = cur.spline.height() - 1;
  std::vector<float>& g = scratch.g;
  out.status = PointStatus::max_iterations;
  for (int it = 1; it <= o.max_iterations; ++it) {
    out.iterations = it;
    // Warp the subset into the current image and sample g there.
    double sum = 0, sum2 = 0;
    for (int k = 0; k < n; ++k) {
      const double x = s.xi_x[k], y = s.xi_y[k];
      double X = c(0) + x + p(0) + p(1) * x + p(2) * y, Y = c(1) + y + p(6) + p(7) * x + p(8) * y;
      if constexpr (NP == 12) {
        X += 0.5 * p(3) * x * x + p(4) * x * y + 0.5 * p(5) * y * y;
        Y += 0.5 * p(9) * x * x + p(10) * x * y + 0.5 * p(11) * y * y;
      }
      if (!(X >= 0 && Y >= 0 && X <= W1 && Y <= H1)) {
        out.status = std::isfinite(X) && std::isfinite(Y) ? PointStatus::out_of_image : PointStatus::diverged;
        out.p = p;
        return out;
      }
      const float v = cur.spline.value(X, Y);
      g[k] = v;
      sum += v;
      sum2 += double(v) * v;
    }
    const double gm = sum / n;
    const double dg = std::sqrt(std::max(0.0, sum2 - n * gm * gm));
    if (!(dg > 1e-12 * df)) {  // the warped subset is blank
      out.status = PointStatus::low_correlation;
      out.zncc = 0;
      out.p = p;
      return out;
    }
    const double ratio = df / dg;
    VecP b = VecP::Zero();
    double cross = 0;
    for (int k = 0; k < n; ++k) {
      const double gk = g[k] - gm;
      cross += s.fc[k] * gk;
      const double r = s.fc[k] - ratio * gk;
      steepest(k);
      b += r * Ji;
    }
    out.zncc = cross / (df * dg);
    const VecP dp = -Hinv.solve(b);
    Shape dP = Shape::Zero();
    if constexpr (NP == 6) {
      dP(0) = dp(0), dP(1) = dp(1), dP(2) = dp(2), dP(6) = dp(3), dP(7) = dp(4), dP(8) = dp(5);
    } else {
      dP = dp;
    }
    p = shape_of(warp_matrix(p) * warp_matrix(dP).inverse());  // W(p) ∘ W(Δp)⁻¹
    out.p = p;
    if (!p.allFinite() || (Mat2::Identity() + displacement_gradient(p)).determinant() < 0.05) {
      out.status = PointStatus::diverged;
      return out;
    }
    double norm2 = dP(0) * dP(0) + dP(6) * dP(6) +
                   half * half * (dP(1) * dP(1) + dP(2) * dP(2) + dP(7) * dP(7) + dP(8) * dP(8));
    if constexpr (NP == 12)
      norm2 += 0.25 * half * half * half * half *
               (dP.segment<3>(3).squaredNorm() + dP.segment<3>(9).squaredNorm());
    if (norm2 < o.tolerance * o.tolerance) {
      out.status = out.zncc >= o.min_zncc ? PointStatus::ok : PointStatus::low_correlation;
      return out;
    }
  }
  return out;
}

}  // namespace

PointMatch icgn(const Frame& reference, const Frame& current, const Vec2& centre, const Shape& guess,
                const IcgnOptions& options) {
  return options.order == ShapeOrder::first ? icgn_order<6>(reference, current, centre, guess, options)
                                            : icgn_order<12>(reference, current, centre, guess, options);
}

bool has_texture(const Frame& reference, const Vec2& centre, const IcgnOptions& options) {
  double df = 0;
  PointStatus s;
  return read_reference(reference, centre, options, df, s);
}

}  // namespace tricot::dic
