// Meshes of the quarter specimen (THEORY §6): nodes, Q4/Q8 elements, and the four edges the test
// models put their boundary conditions on.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "tricot/core/types.hpp"

namespace tricot::fem {

enum class ElementType { Q4, Q8 };
const char* to_string(ElementType t);  ///< "Q4", "Q8"
/// Nodes per element: 4 or 8.
int nodes_per_element(ElementType t);

/// A 2-D mesh. Node n sits at X.col(n) (mm, reference configuration). Element e lists its nodes in
/// `connectivity[e]`: corners counter-clockwise first, then (Q8) the mid-side nodes 4..7 with node
/// 4 between corners 0 and 1, 5 between 1 and 2, and so on. Q4 uses the first four entries only.
struct Mesh {
  ElementType type = ElementType::Q8;
  Eigen::Matrix2Xd X;
  std::vector<std::array<int, 8>> connectivity;
  /// Node sets of the quarter specimen, each sorted by position along the edge.
  std::vector<int> left;    ///< x = 0   (symmetry: u_x = 0)
  std::vector<int> bottom;  ///< y = 0   (symmetry: u_y = 0)
  std::vector<int> top;     ///< y = H   (the grip)
  std::vector<int> right;   ///< x = W   (free edge or lateral guide)

  int nodes() const { return static_cast<int>(X.cols()); }
  int elements() const { return static_cast<int>(connectivity.size()); }
  int dofs() const { return 2 * nodes(); }  ///< dof 2n = u_x of node n, 2n+1 = u_y
};

/// A structured mesh of the rectangle [0, width] × [0, height] (the quarter specimen).
struct MeshOptions {
  double width = 55;    ///< mm, > 0: half the specimen's width (x)
  double height = 55;   ///< mm, > 0: half the specimen's free length (y)
  int nx = 10;          ///< elements along x, 1–2000
  int ny = 10;          ///< elements along y, 1–2000
  ElementType type = ElementType::Q8;
  /// Ratio of the first (y = 0) to the last (y = height) element height, > 0. 1 = uniform;
  /// < 1 refines toward the grip, where the clamp makes the field steep.
  double grading = 1;
  /// Ratio of the first (x = 0) to the last (x = width) element width, > 0. 1 = uniform; < 1 refines
  /// toward the side edge (the guide's end and the free edge of the rig, THEORY §6).
  double grading_x = 1;

  /// Throws InputError naming `mesh.<field>` when out of range.
  void validate() const;
};

Mesh make_quarter_mesh(const MeshOptions& options);

}  // namespace tricot::fem
