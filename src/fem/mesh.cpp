// Element types, mesh checks, and structured meshes of the quarter specimen (docs/theory.md §6).
#include "tricot/fem/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/fem/element.hpp"

namespace tricot::fem {

const char* to_string(ElementType t) {
  switch (t) {
    case ElementType::Q4: return "Q4";
    case ElementType::Q8: return "Q8";
    case ElementType::T3: return "T3";
    case ElementType::T6: return "T6";
  }
  return "?";
}

std::optional<ElementType> element_type(const std::string& name) {
  for (ElementType t : {ElementType::Q4, ElementType::Q8, ElementType::T3, ElementType::T6})
    if (name == to_string(t)) return t;
  return std::nullopt;
}

int nodes_per_element(ElementType t) {
  switch (t) {
    case ElementType::Q4: return 4;
    case ElementType::Q8: return 8;
    case ElementType::T3: return 3;
    case ElementType::T6: return 6;
  }
  return 0;
}

bool is_triangle(ElementType t) { return t == ElementType::T3 || t == ElementType::T6; }

int corners(ElementType t) { return is_triangle(t) ? 3 : 4; }

Vec2 element_centre(ElementType t) { return is_triangle(t) ? Vec2(1.0 / 3, 1.0 / 3) : Vec2(0, 0); }

std::string closest_name(const std::string& word, const std::vector<std::string>& names) {
  // Levenshtein distance; a name within a third of the word's length (at least 2 edits) is a likely typo.
  auto distance = [](const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    std::iota(row.begin(), row.end(), 0);
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t diagonal = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diagonal = up;
      }
    }
    return row[b.size()];
  };
  std::string best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const std::string& n : names) {
    const size_t d = distance(word, n);
    if (d < best_distance) best = n, best_distance = d;
  }
  return best;
}

const std::vector<int>& Mesh::boundary(const std::string& name, const std::string& key) const {
  if (const auto it = boundaries.find(name); it != boundaries.end()) return it->second;
  std::vector<std::string> names;
  for (const auto& [n, nodes] : boundaries) names.push_back(n);
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  const std::string near = closest_name(name, names);
  throw InputError(
      Location{"", 0, key},
      "no boundary of the mesh is named '" + name + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)"),
      "\"" + name + "\"", names.empty() ? "a named boundary (the mesh has none)" : "one of: " + list);
}

void check_mesh(const Mesh& mesh, const std::string& source) {
  auto bad = [&](const std::string& problem, const std::string& got = {}, const std::string& expected = {}) {
    throw InputError(Location{source, 0, "mesh"}, problem, got, expected);
  };
  const int n = mesh.nodes(), ne = mesh.elements(), per = nodes_per_element(mesh.type);
  if (n == 0 || ne == 0)
    bad("empty mesh", std::to_string(n) + " nodes, " + std::to_string(ne) + " elements", "at least one element");
  if (!mesh.X.allFinite()) bad("non-finite node coordinates");
  for (int e = 0; e < ne; ++e)
    for (int a = 0; a < per; ++a)
      if (mesh.connectivity[e][a] < 0 || mesh.connectivity[e][a] >= n)
        bad("element " + std::to_string(e) + " refers to a missing node", std::to_string(mesh.connectivity[e][a]),
            "0 to " + std::to_string(n - 1));
  for (int e = 0; e < ne; ++e) {
    const double det = element_geometry(mesh, e).min_detJ0;
    if (!(det > 0))
      bad("element " + std::to_string(e) + " is inverted or degenerate in the reference mesh",
          "det(dX/dxi) = " + format_number(det), "> 0");
  }
  // One piece: the elements joined through shared nodes (union–find over nodes).
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const auto& c : mesh.connectivity)
    for (int a = 1; a < per; ++a) parent[root(c[a])] = root(c[0]);
  const int first = root(mesh.connectivity[0][0]);
  for (int e = 0; e < ne; ++e)
    if (root(mesh.connectivity[e][0]) != first)
      bad("the mesh is in more than one piece: element " + std::to_string(e) +
              " shares no node, directly or through others, with element 0",
          "", "one connected specimen");
}

void MeshOptions::validate() const {
  auto bad = [](const char* key, const std::string& got, const std::string& expected) {
    throw InputError(Location{"", 0, key}, "out of range", got, expected);
  };
  if (!(width > 0) || !std::isfinite(width)) bad("mesh.width", std::to_string(width), "> 0 mm");
  if (!(height > 0) || !std::isfinite(height)) bad("mesh.height", std::to_string(height), "> 0 mm");
  check_ranges(*this);
  // The declared ranges include their ends: a grading of 0 makes no mesh.
  if (!(grading > 0)) bad("mesh.grading", std::to_string(grading), "> 0");
  if (!(grading_x > 0)) bad("mesh.grading_x", std::to_string(grading_x), "> 0");
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
  const bool quadratic = q8 || o.type == ElementType::T6;
  const int s = quadratic ? 2 : 1;  // grid points per element edge
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
    const double y = quadratic && j % 2 == 1 ? 0.5 * (level[j / 2] + level[j / 2 + 1]) : level[j / s];
    for (int i = 0; i < gx; ++i) {
      const double x = quadratic && i % 2 == 1 ? 0.5 * (column[i / 2] + column[i / 2 + 1]) : column[i / s];
      if (at(i, j) >= 0) m.X.col(at(i, j)) = Vec2(x, y);
    }
  }
  // Exact edges, whatever the rounding of i/(gx−1).
  for (int j = 0; j < gy; ++j)
    if (at(gx - 1, j) >= 0) m.X(0, at(gx - 1, j)) = o.width;

  m.connectivity.reserve(static_cast<size_t>(o.nx) * o.ny * (is_triangle(o.type) ? 2 : 1));
  for (int ey = 0; ey < o.ny; ++ey)
    for (int ex = 0; ex < o.nx; ++ex) {
      const int i = s * ex, j = s * ey;
      std::array<int, 8> c;
      c.fill(-1);
      if (is_triangle(o.type)) {  // the cell split along its diagonal from (i, j) to (i + s, j + s)
        std::array<int, 8> d = c;
        c[0] = at(i, j), c[1] = at(i + s, j), c[2] = at(i + s, j + s);
        d[0] = at(i, j), d[1] = at(i + s, j + s), d[2] = at(i, j + s);
        if (quadratic) {
          c[3] = at(i + 1, j), c[4] = at(i + 2, j + 1), c[5] = at(i + 1, j + 1);
          d[3] = at(i + 1, j + 1), d[4] = at(i + 1, j + 2), d[5] = at(i, j + 1);
        }
        m.connectivity.push_back(c);
        m.connectivity.push_back(d);
        continue;
      }
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
  m.boundaries = {{"left", m.left}, {"bottom", m.bottom}, {"top", m.top}, {"right", m.right}};
  for (auto& [name, nodes] : m.boundaries) std::sort(nodes.begin(), nodes.end());
  return m;
}

}  // namespace tricot::fem
