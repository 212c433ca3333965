// Structured meshes of the quarter specimen (THEORY §6).
#include "tricot/fem/mesh.hpp"

#include <cmath>
#include <string>

#include "tricot/core/error.hpp"

namespace tricot::fem {

const char* to_string(ElementType t) { return t == ElementType::Q4 ? "Q4" : "Q8"; }

int nodes_per_element(ElementType t) { return t == ElementType::Q4 ? 4 : 8; }

void MeshOptions::validate() const {
  auto bad = [](const char* key, const std::string& got, const std::string& expected) {
    throw InputError(Location{"", 0, key}, "out of range", got, expected);
  };
  if (!(width > 0) || !std::isfinite(width)) bad("mesh.width", std::to_string(width), "> 0 mm");
  if (!(height > 0) || !std::isfinite(height)) bad("mesh.height", std::to_string(height), "> 0 mm");
  if (nx < 1 || nx > 2000) bad("mesh.nx", std::to_string(nx), "1 to 2000");
  if (ny < 1 || ny > 2000) bad("mesh.ny", std::to_string(ny), "1 to 2000");
  if (!(grading > 0) || !std::isfinite(grading)) bad("mesh.grading", std::to_string(grading), "> 0");
  if (!(grading_x > 0) || !std::isfinite(grading_x)) bad("mesh.grading_x", std::to_string(grading_x), "> 0");
}

namespace {

// Element boundaries along y: a geometric progression whose first/last element height = grading.
std::vector<double> graded_levels(double height, int ny, double grading) {
  const double r = ny > 1 ? std::pow(grading, -1.0 / (ny - 1)) : 1.0;
  std::vector<double> y(ny + 1, 0.0);
  double h = 1;
  for (int j = 0; j < ny; ++j, h *= r) y[j + 1] = y[j] + h;
  for (double& v : y) v *= height / y[ny];
  y[ny] = height;
  return y;
}

}  // namespace

Mesh make_quarter_mesh(const MeshOptions& o) {
  o.validate();
  const bool q8 = o.type == ElementType::Q8;
  const int s = q8 ? 2 : 1;  // grid points per element edge
  const int gx = s * o.nx + 1, gy = s * o.ny + 1;
  const std::vector<double> level = graded_levels(o.height, o.ny, o.grading);
  const std::vector<double> column = graded_levels(o.width, o.nx, o.grading_x);

  // Grid point (i, j) -> node id; Q8 skips the element centres (odd i and odd j).
  std::vector<int> id(static_cast<size_t>(gx) * gy, -1);
  auto at = [&](int i, int j) -> int& { return id[static_cast<size_t>(j) * gx + i]; };
  int n = 0;
  for (int j = 0; j < gy; ++j)
    for (int i = 0; i < gx; ++i)
      if (!(q8 && i % 2 == 1 && j % 2 == 1)) at(i, j) = n++;

  Mesh m;
  m.type = o.type;
  m.X.resize(2, n);
  for (int j = 0; j < gy; ++j) {
    // Mid-side rows of Q8 sit half-way between their element's levels: straight-sided elements.
    const double y = q8 && j % 2 == 1 ? 0.5 * (level[j / 2] + level[j / 2 + 1]) : level[j / s];
    for (int i = 0; i < gx; ++i) {
      const double x = q8 && i % 2 == 1 ? 0.5 * (column[i / 2] + column[i / 2 + 1]) : column[i / s];
      if (at(i, j) >= 0) m.X.col(at(i, j)) = Vec2(x, y);
    }
  }
  // Exact edges, whatever the rounding of i/(gx−1).
  for (int j = 0; j < gy; ++j)
    if (at(gx - 1, j) >= 0) m.X(0, at(gx - 1, j)) = o.width;

  m.connectivity.reserve(static_cast<size_t>(o.nx) * o.ny);
  for (int ey = 0; ey < o.ny; ++ey)
    for (int ex = 0; ex < o.nx; ++ex) {
      const int i = s * ex, j = s * ey;
      std::array<int, 8> c;
      c.fill(-1);
      c[0] = at(i, j), c[1] = at(i + s, j), c[2] = at(i + s, j + s), c[3] = at(i, j + s);
      if (q8) c[4] = at(i + 1, j), c[5] = at(i + 2, j + 1), c[6] = at(i + 1, j + 2), c[7] = at(i, j + 1);
      m.connectivity.push_back(c);
    }

  for (int j = 0; j < gy; ++j) {
    if (at(0, j) >= 0) m.left.push_back(at(0, j));
    if (at(gx - 1, j) >= 0) m.right.push_back(at(gx - 1, j));
  }
  for (int i = 0; i < gx; ++i) {
    m.bottom.push_back(at(i, 0));
    m.top.push_back(at(i, gy - 1));
  }
  return m;
}

}  // namespace tricot::fem
