// FE values at DIC points (docs/theory.md §7, paper's "capable angles"): finding the element that holds a
// point, the inverse isoparametric map, and interpolation of the displacement there.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "tricot/fem/mesh.hpp"

namespace tricot::fem {

/// Where a point lies in a mesh: element e and natural coordinates ξ in its reference element
/// ([−1, 1]² for quadrilaterals; ξ, η ≥ 0, ξ + η ≤ 1 for triangles).
struct Location {
  int element = -1;
  Vec2 xi = Vec2::Zero();
};

/// Locates points in a mesh, either in its reference configuration or in a deformed one (X + u).
/// A uniform bounding-box grid keeps each query O(1) in the number of elements.
class PointLocator {
 public:
  /// `u` (optional, 2·nodes) deforms the mesh: points are then located in the current configuration.
  explicit PointLocator(const Mesh& mesh, const Eigen::VectorXd* u = nullptr);
  /// The element holding p (by the capable-angles test, then Newton on the isoparametric map), or
  /// nullopt when p is outside the mesh (tolerance: 1e-9 of the element size).
  std::optional<Location> locate(const Vec2& p) const;

 private:
  const Mesh* mesh_;
  Eigen::Matrix2Xd x_;  // node positions used
  Vec2 lo_, cell_;
  int gx_ = 1, gy_ = 1;
  std::vector<std::vector<int>> grid_;
};

/// Shape functions N(ξ) of an element (3, 4, 6 or 8 values).
Eigen::VectorXd shape_functions(ElementType type, const Vec2& xi);
/// Σ_a N_a(ξ) v_a over the element's nodes, for a nodal field v of 2 values per node (u, or a
/// column of du/dc).
Vec2 interpolate(const Mesh& mesh, const Location& at, const Eigen::VectorXd& v);
/// The 2 × dofs row block that interpolate() applies (sparse in practice: 2·(4 or 8) non-zeros),
/// returned as (dof index, weight) per component: value_i = Σ w · v(dof).
struct Interpolant {
  std::vector<int> dofs_x, dofs_y;
  std::vector<double> w;  ///< shared by both components
};
Interpolant interpolant(const Mesh& mesh, const Location& at);

}  // namespace tricot::fem
