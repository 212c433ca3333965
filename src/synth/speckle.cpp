// Continuous speckle rendering (see speckle.hpp).
#include "tricot/synth/speckle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <thread>

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

SpecklePattern::SpecklePattern(const SpeckleOptions& o, double x_min, double y_min, double x_max, double y_max)
    : options_(o) {
  o.validate();
  const double r_max = o.radius * (1 + o.radius_spread);
  const double margin = 3 * r_max;
  cell_ = 3 * r_max;  // a blob further than 3 r contributes < e⁻⁹ and is skipped
  x0_ = x_min - margin;
  y0_ = y_min - margin;
  nx_ = std::max(1, static_cast<int>(std::ceil((x_max - x_min + 2 * margin) / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil((y_max - y_min + 2 * margin) / cell_)));
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  const double area = nx_ * cell_ * ny_ * cell_;
  const auto count = static_cast<std::size_t>(std::llround(o.coverage * area / (std::numbers::pi * o.radius * o.radius)));
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> ux(x0_, x0_ + nx_ * cell_), uy(y0_, y0_ + ny_ * cell_),
      ur(o.radius * (1 - o.radius_spread), o.radius * (1 + o.radius_spread));
  for (std::size_t k = 0; k < count; ++k) {
    const double x = ux(rng), y = uy(rng), r = ur(rng);
    const int i = std::min(nx_ - 1, static_cast<int>((x - x0_) / cell_));
    const int j = std::min(ny_ - 1, static_cast<int>((y - y0_) / cell_));
    cells_[std::size_t(j) * nx_ + i].push_back({float(x), float(y), float(1 / (r * r))});
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
        const float q = (dx * dx + dy * dy) * b.inv_r2;
        if (q < 9.0f) S += std::exp(-q);
      }
  return options_.background + options_.contrast * (1 - std::exp(-S));
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
