// Local least-squares strain (see strain.hpp).
#include "tricot/dic/strain.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <numbers>
#include <algorithm>
#include <vector>

#include "tricot/core/error.hpp"

namespace tricot::dic {

void StrainOptions::validate() const {
  if (window < 3 || window > 51 || window % 2 == 0)
    throw InputError(Location{"", 0, "strain.window"}, window >= 3 && window <= 51 ? "must be odd" : "out of range",
                     std::to_string(window), "an odd number from 3 to 51");
  check_ranges(*this);
}

int virtual_strain_gauge(int subset_size, int step, int window) { return (window - 1) * step + subset_size; }

double strain_transfer(double period, int subset_size, int step, int window) {
  const double w = 2 * std::numbers::pi / period;
  double num = 0, den = 0;
  for (int k = -(window / 2); k <= window / 2; ++k) num += k * std::sin(w * k * step), den += double(k) * k;
  const double fit = num / (w * step * den);
  const double a = std::numbers::pi * subset_size / period;
  return (subset_size > 0 ? std::sin(a) / a : 1.0) * fit;
}

std::vector<StrainPoint> green_lagrange(const std::vector<GridPoint>& grid, const std::vector<Vec2>& x,
                                        const std::vector<char>& good, const StrainOptions& o) {
  o.validate();
  // Grid indices → point, a dense table over the grid's bounding box (−1 where there is no point).
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  if (!grid.empty()) i0 = i1 = grid[0].i, j0 = j1 = grid[0].j;
  for (const GridPoint& g : grid)
    i0 = std::min(i0, g.i), i1 = std::max(i1, g.i), j0 = std::min(j0, g.j), j1 = std::max(j1, g.j);
  const long long width = i1 - i0 + 1;
  std::vector<int> index(static_cast<std::size_t>(std::max(0LL, width * (j1 - j0 + 1))), -1);
  for (int k = 0; k < static_cast<int>(grid.size()); ++k) index[(grid[k].j - j0) * width + (grid[k].i - i0)] = k;
  const auto point_at = [&](int i, int j) {
    return i < i0 || i > i1 || j < j0 || j > j1 ? -1 : index[(j - j0) * width + (i - i0)];
  };
  const int h = o.window / 2;
  const int needed = std::max(4, static_cast<int>(std::ceil(o.min_fraction * o.window * o.window)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<StrainPoint> out(grid.size());
  // Each point's fit is independent of the others': in parallel (issue 16).
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < grid.size(); ++k) {
    StrainPoint& s = out[k];
    s.exx = s.eyy = s.exy = nan;
    if (!good[k]) continue;
    // Normal equations of x = a + F (X − X_c) for each component, with 1, dX, dY as the basis.
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Matrix<double, 3, 2> b = Eigen::Matrix<double, 3, 2>::Zero();
    int count = 0;
    for (int dj = -h; dj <= h; ++dj)
      for (int di = -h; di <= h; ++di) {
        const int q = point_at(grid[k].i + di, grid[k].j + dj);
        if (q < 0 || !good[q]) continue;
        const Vec2 dX = grid[q].x - grid[k].x;
        const Eigen::Vector3d phi(1, dX(0), dX(1));
        A += phi * phi.transpose();
        b += phi * x[q].transpose();
        ++count;
      }
    if (count < needed) continue;
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
    if (lu.rank() < 3) continue;  // neighbours on a line
    const Eigen::Matrix<double, 3, 2> c = lu.solve(b);
    s.F = c.bottomRows<2>().transpose();  // F(i, a) = ∂x_i/∂X_a
    const Mat2 E = 0.5 * (s.F.transpose() * s.F - Mat2::Identity());
    s.exx = E(0, 0), s.eyy = E(1, 1), s.exy = E(0, 1);
    s.valid = true;
  }
  return out;
}

}  // namespace tricot::dic
