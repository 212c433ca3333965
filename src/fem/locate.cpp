// Point location in a mesh (docs/theory.md §7): a uniform grid of element bounding boxes gives the
// candidates, the paper's "capable angles" test picks the element, Newton on the isoparametric map
// gives ξ.
#include "tricot/fem/locate.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "tricot/fem/element.hpp"

namespace tricot::fem {

namespace {

// Natural-coordinate tolerance: an element spans 2 in ξ, so 2e-9 is 1e-9 of its size.
constexpr double kXiTolerance = 2e-9;
// Newton on the isoparametric map stops when |Δξ| falls below this (well under kXiTolerance).
constexpr double kNewtonTolerance = 1e-13;
constexpr int kNewtonIterations = 50;

// The element's boundary polygon, counter-clockwise: the corners of a linear element; corners and
// mid-side nodes (0 4 1 5 2 6 3 7 for Q8, 0 3 1 4 2 5 for T6) of a quadratic one, so that curved edges
// are followed.
int boundary(const Mesh& mesh, const Eigen::Matrix2Xd& x, int e, Vec2* out) {
  const auto& c = mesh.connectivity[e];
  const int k = corners(mesh.type);
  if (nodes_per_element(mesh.type) == k) {
    for (int a = 0; a < k; ++a) out[a] = x.col(c[a]);
    return k;
  }
  for (int a = 0; a < k; ++a) {
    out[2 * a] = x.col(c[a]);
    out[2 * a + 1] = x.col(c[k + a]);
  }
  return 2 * k;
}

// The paper's capable-angles test: the signed angles that p makes with each pair of consecutive
// boundary nodes sum to ±2π when p is inside and to 0 when outside (±π on an edge).
bool capable_angles_inside(const Vec2* poly, int n, const Vec2& p, double size) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const Vec2 a = poly[i] - p, b = poly[(i + 1) % n] - p;
    if (a.norm() <= 1e-12 * size) return true;  // p on a node: the angle is undefined, p is in
    sum += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  }
  return std::abs(sum) > std::numbers::pi;  // half-way between the two values the test can take
}

// Newton on x(ξ) = Σ N_a(ξ) x_a = p. Returns false when the map is singular or Newton does not settle.
bool inverse_map(const Mesh& mesh, const Eigen::Matrix2Xd& x, int e, const Vec2& p, Vec2& xi) {
  const int n = nodes_per_element(mesh.type);
  const auto& c = mesh.connectivity[e];
  xi = element_centre(mesh.type);
  for (int it = 0; it < kNewtonIterations; ++it) {
    const ShapeValues s = shape(mesh.type, xi);
    Vec2 xp = Vec2::Zero();
    Mat2 J = Mat2::Zero();  // ∂x/∂ξ
    for (int a = 0; a < n; ++a) {
      xp += s.N(a) * x.col(c[a]);
      J += x.col(c[a]) * s.dN_dxi.row(a);
    }
    const double det = J.determinant();
    if (!(std::abs(det) > 0)) return false;
    const Vec2 step = J.inverse() * (p - xp);
    xi += step;
    xi = xi.cwiseMax(-3).cwiseMin(3);  // keep far-away trials from wandering off
    if (step.norm() < kNewtonTolerance) return true;
  }
  return false;
}

// Inside the reference element within the tolerance: [−1, 1]², or the triangle ξ, η ≥ 0, ξ + η ≤ 1
// (which spans 1 in ξ: half the tolerance).
bool within(ElementType type, const Vec2& xi) {
  if (is_triangle(type)) return xi.minCoeff() >= -0.5 * kXiTolerance && xi.sum() <= 1 + 0.5 * kXiTolerance;
  return xi.cwiseAbs().maxCoeff() <= 1 + kXiTolerance;
}

// ξ moved onto the reference element.
Vec2 clamp_to(ElementType type, Vec2 xi) {
  if (!is_triangle(type)) return xi.cwiseMax(-1).cwiseMin(1);
  xi = xi.cwiseMax(0);
  if (const double sum = xi.sum(); sum > 1) xi /= sum;
  return xi;
}

}  // namespace

PointLocator::PointLocator(const Mesh& mesh, const Eigen::VectorXd* u) : mesh_(&mesh), x_(mesh.X) {
  if (u) {
    assert(u->size() == mesh.dofs());
    for (int n = 0; n < mesh.nodes(); ++n) x_.col(n) += u->segment<2>(2 * n);
  }
  const int ne = mesh.elements();
  const int nn = nodes_per_element(mesh.type);
  lo_ = Vec2::Constant(INFINITY);
  Vec2 hi = Vec2::Constant(-INFINITY);
  std::vector<Eigen::AlignedBox2d> boxes(ne);
  for (int e = 0; e < ne; ++e) {
    for (int a = 0; a < nn; ++a) boxes[e].extend(x_.col(mesh.connectivity[e][a]));
    // Q8 edges bulge past their nodes by at most a quarter of the mid-node's offset; pad for it.
    boxes[e].extend(boxes[e].min() - 0.25 * boxes[e].sizes());
    boxes[e].extend(boxes[e].max() + 0.25 * boxes[e].sizes());
    lo_ = lo_.cwiseMin(boxes[e].min());
    hi = hi.cwiseMax(boxes[e].max());
  }
  if (ne == 0) return;
  // About one element per cell.
  const Vec2 span = (hi - lo_).cwiseMax(1e-300);
  gx_ = std::clamp(static_cast<int>(std::lround(std::sqrt(ne * span.x() / span.y()))), 1, 4096);
  gy_ = std::clamp(static_cast<int>(std::lround(static_cast<double>(ne) / gx_)), 1, 4096);
  cell_ = Vec2(span.x() / gx_, span.y() / gy_);
  grid_.assign(static_cast<size_t>(gx_) * gy_, {});
  for (int e = 0; e < ne; ++e) {
    const int i0 = std::clamp(static_cast<int>((boxes[e].min().x() - lo_.x()) / cell_.x()), 0, gx_ - 1);
    const int i1 = std::clamp(static_cast<int>((boxes[e].max().x() - lo_.x()) / cell_.x()), 0, gx_ - 1);
    const int j0 = std::clamp(static_cast<int>((boxes[e].min().y() - lo_.y()) / cell_.y()), 0, gy_ - 1);
    const int j1 = std::clamp(static_cast<int>((boxes[e].max().y() - lo_.y()) / cell_.y()), 0, gy_ - 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) grid_[static_cast<size_t>(j) * gx_ + i].push_back(e);
  }
}

std::optional<Location> PointLocator::locate(const Vec2& p) const {
  if (grid_.empty() || !p.allFinite()) return std::nullopt;
  const Vec2 r = (p - lo_).cwiseQuotient(cell_);
  if (r.x() < 0 || r.y() < 0 || r.x() > gx_ || r.y() > gy_) return std::nullopt;
  const int i = std::min(static_cast<int>(r.x()), gx_ - 1), j = std::min(static_cast<int>(r.y()), gy_ - 1);
  const auto& candidates = grid_[static_cast<size_t>(j) * gx_ + i];

  Vec2 poly[8];
  Vec2 xi;
  // First pass: the capable-angles test picks the element, Newton confirms (Q8: ξ within ±tol).
  for (int e : candidates) {
    const int n = boundary(*mesh_, x_, e, poly);
    Eigen::AlignedBox2d box;
    for (int a = 0; a < n; ++a) box.extend(poly[a]);
    const double size = box.sizes().maxCoeff();
    if (!capable_angles_inside(poly, n, p, size)) continue;
    if (inverse_map(*mesh_, x_, e, p, xi) && within(mesh_->type, xi)) return Location{e, clamp_to(mesh_->type, xi)};
  }
  // Second pass: points on an edge (the angle sum is ±π), within the tolerance outside it, or in
  // the bulge of a curved Q8 edge beyond its boundary polygon: Newton alone decides.
  for (int e : candidates)
    if (inverse_map(*mesh_, x_, e, p, xi) && within(mesh_->type, xi)) return Location{e, clamp_to(mesh_->type, xi)};
  return std::nullopt;
}

Eigen::VectorXd shape_functions(ElementType type, const Vec2& xi) {
  return shape(type, xi).N.head(nodes_per_element(type));
}

Vec2 interpolate(const Mesh& mesh, const Location& at, const Eigen::VectorXd& v) {
  const ShapeValues s = shape(mesh.type, at.xi);
  const int n = nodes_per_element(mesh.type);
  const auto& c = mesh.connectivity[at.element];
  Vec2 out = Vec2::Zero();
  for (int a = 0; a < n; ++a) out += s.N(a) * v.segment<2>(2 * c[a]);
  return out;
}

Interpolant interpolant(const Mesh& mesh, const Location& at) {
  const ShapeValues s = shape(mesh.type, at.xi);
  const int n = nodes_per_element(mesh.type);
  const auto& c = mesh.connectivity[at.element];
  Interpolant I;
  for (int a = 0; a < n; ++a) {
    I.dofs_x.push_back(2 * c[a]);
    I.dofs_y.push_back(2 * c[a] + 1);
    I.w.push_back(s.N(a));
  }
  return I;
}

}  // namespace tricot::fem
