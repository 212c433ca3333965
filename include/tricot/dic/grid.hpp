// Where DIC measures: a region of interest (rectangle, polygon or mask image) and the grid of subset
// centres inside it (docs/theory.md §10).
#pragma once

#include <array>
#include <vector>

#include "tricot/core/types.hpp"
#include "tricot/image/image.hpp"

namespace tricot::dic {

/// The region of interest in the reference image (px, y down).
struct Roi {
  enum class Kind { whole, rectangle, polygon, mask };
  Kind kind = Kind::whole;
  Vec2 corner0{0, 0}, corner1{0, 0};  ///< rectangle: two opposite corners
  std::vector<Vec2> polygon;          ///< polygon: vertices in order (closed implicitly), ≥ 3
  image::Image mask;                  ///< mask: same size as the reference; pixels > half full scale are inside

  static Roi whole_image() { return {}; }
  static Roi rectangle(double x0, double y0, double x1, double y1);
  static Roi from_polygon(std::vector<Vec2> vertices);
  static Roi from_mask(image::Image m);

  /// Whether the point (x, y) of the reference image is inside the region.
  bool contains(double x, double y) const;
};

/// One subset centre of the grid, with its grid indices (neighbours differ by one in i or j).
struct GridPoint {
  Vec2 x;     ///< centre in the reference image, px (integers for a fixed grid)
  int i = 0;  ///< column index: x = origin + i·step
  int j = 0;  ///< row index
};

/// The grid: subset centres at integer pixels x = i·step + offset (aligned on the ROI's bounding box)
/// whose centre lies in the ROI and whose whole subset lies in the image. Throws InputError (key
/// `dic.roi`) when the ROI is empty, outside the image or holds no centre (the message says why).
std::vector<GridPoint> make_grid(const Roi& roi, int width, int height, int subset_size, int step);

/// For each point, the indices of its four grid neighbours (−1 where there is none).
std::vector<std::array<int, 4>> grid_neighbours(const std::vector<GridPoint>& points);

}  // namespace tricot::dic
