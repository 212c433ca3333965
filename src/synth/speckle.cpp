// Continuous speckle rendering (see speckle.hpp).
#include "tricot/synth/speckle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <thread>

#include <omp.h>

#include "tricot/core/error.hpp"

namespace tricot::synth {

void SpeckleOptions::validate() const {
  auto bad = [](const char* key, double got, const char* expected) {
    throw InputError(Location{"", 0, key}, "out of range", std::to_string(got), expected);
  };
  if (!(radius > 0 && radius < 1000)) bad("speckle.radius", radius, "0 to 1000 px");
  if (!(radius_spread >= 0 && radius_spread <= 0.9)) bad("speckle.radius_spread", radius_spread, "0 to 0.9");
  if (!(coverage > 0 && coverage < 100)) bad("speckle.coverage", coverage, "0 to 100");
  if (!(background >= 0 && background <= 1)) bad("speckle.background", background, "0 to 1");
  if (!(contrast >= 0 && contrast <= 1)) bad("speckle.contrast", contrast, "0 to 1");
  if (subsamples < 1 || subsamples > 16) bad("speckle.subsamples", subsamples, "1 to 16");
}

const char* to_string(Texture t) { return t == Texture::knit ? "knit" : "speckle"; }

std::optional<Texture> texture_from_string(std::string_view word) {
  if (word == "speckle") return Texture::speckle;
  if (word == "knit") return Texture::knit;
  return std::nullopt;
}

namespace {

// Knit stitches in units of the radius r: pitch across the wales 4 r, along them 3.2 r; each leg an
// ellipse of semi-axes 1.6 r × 0.6 r tilted ±30° from the wale, centred ±r from the stitch's axis.
constexpr double kAcross = 4.0, kAlong = 3.2, kLegLong = 1.6, kLegShort = 0.6, kLegOffset = 1.0, kLegTiltDeg = 30;
constexpr double kJitter = 0.25;                            // × r: stitch position scatter (yarn tension varies)
constexpr double kFuzzPerStitch = 0.6, kFuzzRadius = 0.45;  // loose fibres: small round blobs

}  // namespace

SpecklePattern::SpecklePattern(const SpeckleOptions& o, double x_min, double y_min, double x_max, double y_max)
    : options_(o) {
  o.validate();
  const double r_max = o.radius * (1 + o.radius_spread) * (o.texture == Texture::knit ? kLegLong : 1.0);
  const double margin = 3 * r_max;
  cell_ = 3 * r_max;  // a blob further than 3 semi-axes contributes < e⁻⁹ and is skipped
  x0_ = x_min - margin;
  y0_ = y_min - margin;
  nx_ = std::max(1, static_cast<int>(std::ceil((x_max - x_min + 2 * margin) / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil((y_max - y_min + 2 * margin) / cell_)));
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  const double area = nx_ * cell_ * ny_ * cell_;
  if (o.texture == Texture::speckle) {
    scatter_round(
        static_cast<std::uint64_t>(std::llround(o.coverage * area / (std::numbers::pi * o.radius * o.radius))), 1.0,
        1.0, o.seed);
  } else {
    knit_stitches();
    const double stitches = area / (kAcross * kAlong * o.radius * o.radius);
    scatter_round(static_cast<std::uint64_t>(std::llround(kFuzzPerStitch * stitches)), kFuzzRadius, 0.4, o.seed + 1);
  }
}

void SpecklePattern::add(const Blob& blob) {
  const int i = static_cast<int>(std::floor((blob.x - x0_) / cell_));
  const int j = static_cast<int>(std::floor((blob.y - y0_) / cell_));
  if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return;
  cells_[std::size_t(j) * nx_ + i].push_back(blob);
}

void SpecklePattern::scatter_round(std::uint64_t count, double radius_scale, double weight_min, std::uint64_t seed) {
  const SpeckleOptions& o = options_;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(x0_, x0_ + nx_ * cell_), uy(y0_, y0_ + ny_ * cell_),
      ur(radius_scale * o.radius * (1 - o.radius_spread), radius_scale * o.radius * (1 + o.radius_spread)),
      uw(weight_min, 1.0);
  for (std::uint64_t k = 0; k < count; ++k) {
    const double x = ux(rng), y = uy(rng), r = ur(rng);
    const float inv = float(1 / (r * r));
    add({float(x), float(y), inv, 0.0f, inv, float(weight_min < 1 ? uw(rng) : 1.0)});
  }
}

void SpecklePattern::knit_stitches() {
  const SpeckleOptions& o = options_;
  const double r = o.radius, th = o.wale_angle_deg * std::numbers::pi / 180;
  const Vec2 w(std::cos(th), std::sin(th)), c(-w(1), w(0));  // along and across the wales
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> jitter(0, kJitter * r);
  std::uniform_real_distribution<double> size(1 - o.radius_spread, 1 + o.radius_spread), weight(0.55, 1.0);
  // The lattice covers the pattern's rectangle in any orientation: index range from its corners.
  const double X0 = x0_, Y0 = y0_, X1 = x0_ + nx_ * cell_, Y1 = y0_ + ny_ * cell_;
  double a_min = 1e300, a_max = -1e300, b_min = 1e300, b_max = -1e300;
  for (const Vec2& p : {Vec2(X0, Y0), Vec2(X1, Y0), Vec2(X0, Y1), Vec2(X1, Y1)}) {
    a_min = std::min(a_min, p.dot(c)), a_max = std::max(a_max, p.dot(c));
    b_min = std::min(b_min, p.dot(w)), b_max = std::max(b_max, p.dot(w));
  }
  const double across = kAcross * r, along = kAlong * r;
  for (long i = std::lround(std::floor(a_min / across)); i <= std::lround(std::ceil(a_max / across)); ++i)
    for (long j = std::lround(std::floor(b_min / along)); j <= std::lround(std::ceil(b_max / along)); ++j) {
      const Vec2 stitch = (i * across + jitter(rng)) * c + (j * along + jitter(rng)) * w;
      const double scale = size(rng);
      for (int side : {-1, 1}) {
        // A leg: long axis tilted from the wale toward the stitch's axis (the V opens along +w).
        const double tilt = side * kLegTiltDeg * std::numbers::pi / 180;
        const Vec2 e1 = std::cos(tilt) * w - std::sin(tilt) * c, e2(-e1(1), e1(0));
        const double l = kLegLong * r * scale, t = kLegShort * r * scale;
        const Mat2 M = e1 * e1.transpose() / (l * l) + e2 * e2.transpose() / (t * t);
        const Vec2 x = stitch + side * kLegOffset * r * c;
        add({float(x(0)), float(x(1)), float(M(0, 0)), float(M(0, 1)), float(M(1, 1)), float(weight(rng))});
      }
    }
}

double SpecklePattern::intensity(const Vec2& X) const {
  const int i = static_cast<int>(std::floor((X(0) - x0_) / cell_));
  const int j = static_cast<int>(std::floor((X(1) - y0_) / cell_));
  // Each blob's term in single precision (relative error ~1e-7, far below any effect on DIC), the sum
  // and the saturation in double.
  double S = 0;
  for (int jj = std::max(0, j - 1); jj <= std::min(ny_ - 1, j + 1); ++jj)
    for (int ii = std::max(0, i - 1); ii <= std::min(nx_ - 1, i + 1); ++ii)
      for (const Blob& b : cells_[std::size_t(jj) * nx_ + ii]) {
        const float dx = static_cast<float>(X(0) - b.x), dy = static_cast<float>(X(1) - b.y);
        const float q = b.a * dx * dx + 2 * b.b * dx * dy + b.c * dy * dy;
        if (q < 9.0f) S += b.weight * std::exp(-q);
      }
  return options_.background + options_.contrast * (1 - std::exp(-S));
}

image::Image SpecklePattern::intensity_grid(double x0, double y0, double h, int nx, int ny) const {
  // S at the nodes, blob by blob: a blob adds to the nodes inside its ellipse q < 9, whose half-widths
  // are 3·√((M⁻¹)₁₁) across x and 3·√((M⁻¹)₂₂) across y. Every blob that intensity() would count at a
  // node (one of the 3 × 3 cells around it, q < 9) is counted here, with the same single-precision q.
  // S is summed in the image's floats (a sum of a few terms ≤ 1: relative error ~1e-7), in strips of
  // rows, one thread each: a strip takes the blobs of the cell rows that reach it.
  image::Image I(nx, ny, 0.0f, 1.0);
  const int strips = std::max(1, std::min(ny / 64, 4 * omp_get_max_threads()));
#pragma omp parallel for schedule(dynamic, 1)
  for (int strip = 0; strip < strips; ++strip) {
    const int row_begin = static_cast<int>(std::int64_t(ny) * strip / strips);
    const int row_end = static_cast<int>(std::int64_t(ny) * (strip + 1) / strips);
    const double top = y0 + row_begin * h, bottom = y0 + (row_end - 1) * h;
    const int cell_begin = std::max(0, static_cast<int>(std::floor((top - y0_) / cell_)) - 1);
    const int cell_end = std::min(ny_ - 1, static_cast<int>(std::floor((bottom - y0_) / cell_)) + 1);
    for (int cj = cell_begin; cj <= cell_end; ++cj)
      for (int ci = 0; ci < nx_; ++ci)
        for (const Blob& b : cells_[std::size_t(cj) * nx_ + ci]) {
          const double det = double(b.a) * b.c - double(b.b) * b.b;
          const double ex = 3 * std::sqrt(b.c / det), ey = 3 * std::sqrt(b.a / det);
          const int i0 = std::max(0, static_cast<int>(std::ceil((b.x - ex - x0) / h)));
          const int i1 = std::min(nx - 1, static_cast<int>(std::floor((b.x + ex - x0) / h)));
          const int j0 = std::max(row_begin, static_cast<int>(std::ceil((b.y - ey - y0) / h)));
          const int j1 = std::min(row_end - 1, static_cast<int>(std::floor((b.y + ey - y0) / h)));
          for (int j = j0; j <= j1; ++j) {
            const float dy = static_cast<float>(y0 + j * h - b.y);
            float* row = I.pixels.data() + std::size_t(j) * nx;
            for (int i = i0; i <= i1; ++i) {
              const float dx = static_cast<float>(x0 + i * h - b.x);
              const float q = b.a * dx * dx + 2 * b.b * dx * dy + b.c * dy * dy;
              if (q < 9.0f) row[i] += b.weight * std::exp(-q);
            }
          }
        }
    for (int j = row_begin; j < row_end; ++j) {
      float* row = I.pixels.data() + std::size_t(j) * nx;
      for (int i = 0; i < nx; ++i)
        row[i] = static_cast<float>(options_.background + options_.contrast * (1 - std::exp(-double(row[i]))));
    }
  }
  return I;
}

double SpecklePattern::smallest_radius() const {
  const SpeckleOptions& o = options_;
  const double shrink = 1 - o.radius_spread;
  return o.texture == Texture::knit ? std::min(kFuzzRadius, kLegShort) * o.radius * shrink : o.radius * shrink;
}

PatternTable::PatternTable(const SpecklePattern& pattern, double x_min, double y_min, double x_max, double y_max)
    : pattern_(&pattern) {
  const double h = std::min(0.25, 0.45 * pattern.smallest_radius());
  // One node beyond the rectangle on each side: the B-spline is exact on the grid's inside only.
  const double nx = std::ceil((x_max - x_min) / h) + 3, ny = std::ceil((y_max - y_min) / h) + 3;
  if (!(nx * ny <= kMaxNodes) || !(nx >= 2 && ny >= 2)) return;
  x0_ = x_min - h;
  y0_ = y_min - h;
  step_ = h;
  inverse_step_ = 1 / h;
  spline_ = image::BSplineImage(pattern.intensity_grid(x0_, y0_, h, static_cast<int>(nx), static_cast<int>(ny)));
}

image::Image render(const SpecklePattern& pattern, int width, int height, const InverseMotion& motion, int threads) {
  image::Image img(width, height, 0.0f, 1.0);
  const int s = pattern.options().subsamples;
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const int nt = std::max(1, std::min(threads > 0 ? threads : static_cast<int>(hw), height));
  auto rows = [&](int t) {
    for (int y = t; y < height; y += nt)
      for (int x = 0; x < width; ++x) {
        double sum = 0;
        for (int b = 0; b < s; ++b)
          for (int a = 0; a < s; ++a) {
            // sub-sample centres of the pixel square [x − ½, x + ½] × [y − ½, y + ½]
            const Vec2 xs(x - 0.5 + (a + 0.5) / s, y - 0.5 + (b + 0.5) / s);
            sum += pattern.intensity(motion(xs));
          }
        img.at(x, y) = static_cast<float>(sum / (s * s));
      }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < nt; ++t) pool.emplace_back(rows, t);
  rows(0);
  for (auto& th : pool) th.join();
  return img;
}

image::Image add_noise(const image::Image& img, double sigma, std::uint64_t seed) {
  image::Image out = img;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0, sigma * img.full_scale);
  for (auto& p : out.pixels) p = static_cast<float>(p + n(rng));
  return out;
}

}  // namespace tricot::synth
