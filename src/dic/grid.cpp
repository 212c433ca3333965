// Region of interest and grid of subset centres.
#include "tricot/dic/grid.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "tricot/core/error.hpp"

namespace tricot::dic {

Roi Roi::rectangle(double x0, double y0, double x1, double y1) {
  Roi r;
  r.kind = Kind::rectangle;
  r.corner0 = Vec2(std::min(x0, x1), std::min(y0, y1));
  r.corner1 = Vec2(std::max(x0, x1), std::max(y0, y1));
  return r;
}

Roi Roi::from_polygon(std::vector<Vec2> vertices) {
  if (vertices.size() < 3)
    throw InputError(Location{"", 0, "dic.roi.polygon"}, "a polygon needs at least 3 vertices",
                     std::to_string(vertices.size()), ">= 3");
  Roi r;
  r.kind = Kind::polygon;
  r.polygon = std::move(vertices);
  return r;
}

Roi Roi::from_mask(image::Image m) {
  Roi r;
  r.kind = Kind::mask;
  r.mask = std::move(m);
  return r;
}

bool Roi::contains(double x, double y) const {
  switch (kind) {
    case Kind::whole: return true;
    case Kind::rectangle: return x >= corner0(0) && x <= corner1(0) && y >= corner0(1) && y <= corner1(1);
    case Kind::polygon: {  // even–odd ray casting
      bool in = false;
      for (std::size_t a = 0, b = polygon.size() - 1; a < polygon.size(); b = a++) {
        const Vec2 &p = polygon[a], &q = polygon[b];
        if ((p(1) > y) != (q(1) > y) && x < (q(0) - p(0)) * (y - p(1)) / (q(1) - p(1)) + p(0)) in = !in;
      }
      return in;
    }
    case Kind::mask: {
      const int ix = static_cast<int>(std::lround(x)), iy = static_cast<int>(std::lround(y));
      if (ix < 0 || iy < 0 || ix >= mask.width || iy >= mask.height) return false;
      return mask.at(ix, iy) > 0.5 * mask.full_scale;
    }
  }
  return false;
}

std::vector<GridPoint> make_grid(const Roi& roi, int width, int height, int subset_size, int step) {
  const Location where{"", 0, "dic.roi"};
  if (step < 1) throw InputError(Location{"", 0, "dic.step"}, "out of range", std::to_string(step), ">= 1 px");
  // Bounding box of the ROI, clipped to the image.
  double bx0 = 0, by0 = 0, bx1 = width - 1, by1 = height - 1;
  if (roi.kind == Roi::Kind::rectangle) {
    bx0 = roi.corner0(0), by0 = roi.corner0(1), bx1 = roi.corner1(0), by1 = roi.corner1(1);
  } else if (roi.kind == Roi::Kind::polygon) {
    bx0 = by0 = 1e300, bx1 = by1 = -1e300;
    for (const Vec2& v : roi.polygon)
      bx0 = std::min(bx0, v(0)), by0 = std::min(by0, v(1)), bx1 = std::max(bx1, v(0)), by1 = std::max(by1, v(1));
  } else if (roi.kind == Roi::Kind::mask && (roi.mask.width != width || roi.mask.height != height)) {
    throw InputError(where, "mask image size differs from the reference image",
                     std::to_string(roi.mask.width) + "x" + std::to_string(roi.mask.height),
                     std::to_string(width) + "x" + std::to_string(height));
  }
  auto box = [](double a, double b, double c, double d) {
    auto f = [](double v) { return std::to_string(static_cast<long long>(std::lround(v))); };
    return f(a) + "," + f(b) + "," + f(c) + "," + f(d);
  };
  if (bx1 < 0 || by1 < 0 || bx0 > width - 1 || by0 > height - 1)
    throw InputError(where, "region of interest lies outside the image", box(bx0, by0, bx1, by1),
                     "within 0,0," + std::to_string(width - 1) + "," + std::to_string(height - 1));
  const int M = subset_size / 2;
  const int x_lo = std::max(M, static_cast<int>(std::ceil(bx0))),
            x_hi = std::min(width - 1 - M, static_cast<int>(std::floor(bx1)));
  const int y_lo = std::max(M, static_cast<int>(std::ceil(by0))),
            y_hi = std::min(height - 1 - M, static_cast<int>(std::floor(by1)));
  std::vector<GridPoint> points;
  for (int y = y_lo, j = 0; y <= y_hi; y += step, ++j)
    for (int x = x_lo, i = 0; x <= x_hi; x += step, ++i)
      if (roi.contains(x, y)) points.push_back({Vec2(x, y), i, j});
  if (points.empty())
    throw InputError(where, "no subset fits in the region of interest", box(bx0, by0, bx1, by1),
                     "a region holding at least one " + std::to_string(subset_size) + " px subset inside the " +
                         std::to_string(width) + "x" + std::to_string(height) + " image");
  return points;
}

std::vector<std::array<int, 4>> grid_neighbours(const std::vector<GridPoint>& points) {
  std::map<std::pair<int, int>, int> index;
  for (int k = 0; k < static_cast<int>(points.size()); ++k) index[{points[k].i, points[k].j}] = k;
  std::vector<std::array<int, 4>> out(points.size());
  const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
  for (std::size_t k = 0; k < points.size(); ++k)
    for (int d = 0; d < 4; ++d) {
      auto it = index.find({points[k].i + di[d], points[k].j + dj[d]});
      out[k][d] = it == index.end() ? -1 : it->second;
    }
  return out;
}

}  // namespace tricot::dic
