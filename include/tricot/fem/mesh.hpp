// Meshes (docs/theory.md §6): nodes, T3/T6/Q4/Q8 elements, regions, and named boundaries (node sets) that
// the test models put their boundary conditions on. The built-in generator of the quarter specimen
// names its four edges as a Gmsh file names its physical curves, so one path serves every mesh.
#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "tricot/core/options.hpp"
#include "tricot/core/types.hpp"

namespace tricot::fem {

/// Linear and quadratic triangles and quadrilaterals (Gmsh's element types 2, 9, 3 and 16).
enum class ElementType { Q4, Q8, T3, T6 };
const char* to_string(ElementType t);  ///< "Q4", "Q8", "T3", "T6"
/// The type named `name` ("T3", "T6", "Q4", "Q8"), or nullopt.
std::optional<ElementType> element_type(const std::string& name);
/// Nodes per element: 3, 6, 4 or 8.
int nodes_per_element(ElementType t);
/// Corner nodes per element: 3 or 4.
int corners(ElementType t);
bool is_triangle(ElementType t);
/// The element's centre in natural coordinates: (0, 0) for quadrilaterals, (1/3, 1/3) for triangles.
Vec2 element_centre(ElementType t);

/// A 2-D mesh. Node n sits at X.col(n) (mm, reference configuration). Element e lists its nodes in
/// `connectivity[e]` in Gmsh's (and VTK's) order: corners counter-clockwise first, then the mid-side
/// nodes of the quadratic types, the first between corners 0 and 1, the next between 1 and 2, and so
/// on. Entries past nodes_per_element(type) are unused.
struct Mesh {
  ElementType type = ElementType::Q8;
  Eigen::Matrix2Xd X;
  std::vector<std::array<int, 8>> connectivity;
  /// Node sets of the quarter specimen (make_quarter_mesh), each sorted by position along the edge;
  /// they are also named in `boundaries`. Empty in a mesh read from a file.
  std::vector<int> left;    ///< x = 0   (symmetry: u_x = 0)
  std::vector<int> bottom;  ///< y = 0   (symmetry: u_y = 0)
  std::vector<int> top;     ///< y = H   (the grip)
  std::vector<int> right;   ///< x = W   (free edge or lateral guide)
  /// Named boundaries: sorted node sets (a Gmsh file's physical curves and points; the quarter's
  /// "left", "bottom", "top" and "right").
  std::map<std::string, std::vector<int>> boundaries;
  /// Region of each element, an index into region_names (a Gmsh file's physical surfaces); empty =
  /// one region for every element.
  std::vector<int> region;
  std::vector<std::string> region_names;

  int nodes() const { return static_cast<int>(X.cols()); }
  int elements() const { return static_cast<int>(connectivity.size()); }
  int dofs() const { return 2 * nodes(); }  ///< dof 2n = u_x of node n, 2n+1 = u_y
  /// The node set named `name`; InputError naming `key` (with a did-you-mean) when there is none.
  const std::vector<int>& boundary(const std::string& name, const std::string& key = "boundary") const;
};

/// The closest of `names` to `word` by edit distance when it is close enough to be a likely typo, else
/// empty: the did-you-mean of an error message.
std::string closest_name(const std::string& word, const std::vector<std::string>& names);

/// Throws InputError (key `mesh`, file `source`) when the mesh is not a usable 2-D specimen: an element
/// that refers to a missing node, an inverted or degenerate element (det ∂X/∂ξ ≤ 0 at a quadrature
/// point), or elements in more than one connected piece.
void check_mesh(const Mesh& mesh, const std::string& source = "");

/// A structured mesh of the rectangle [0, width] × [0, height] (the quarter specimen).
struct MeshOptions {
  double width = 55;   ///< mm, > 0: half the specimen's width (x)
  double height = 55;  ///< mm, > 0: half the specimen's free length (y)
  int nx = 10;         ///< elements along x, 1–2000
  int ny = 10;         ///< elements along y, 1–2000
  ElementType type = ElementType::Q8;
  /// Ratio of the first (y = 0) to the last (y = height) element height, > 0 and at most 1e3.
  /// 1 = uniform; < 1 refines toward the grip, where the clamp makes the field steep.
  double grading = 1;
  /// Ratio of the first (x = 0) to the last (x = width) element width, > 0 and at most 1e3.
  /// 1 = uniform; < 1 refines toward the side edge (the guide's end and the free edge of the rig,
  /// docs/theory.md §6).
  double grading_x = 1;

  /// The config keys of [mesh] these options hold (core/options.hpp). width and height are the
  /// quarter's: [mesh] gives the full specimen's (project::MeshSpec).
  static auto keys() {
    using O = MeshOptions;
    return std::tuple{
        option(&O::type, "mesh.element",
               "Element type: Q8 serendipity (the paper's), Q4 bilinear, T3 linear or T6 quadratic triangles (the\n"
               "generator splits each cell; a meshed geometry takes T3/T6, or Q4/Q8 by recombining).",
               {{ElementType::Q4, "Q4"}, {ElementType::Q8, "Q8"}, {ElementType::T3, "T3"}, {ElementType::T6, "T6"}}),
        option(&O::nx, "mesh.nx", "Elements across the quarter's width.", 1, 2000),
        option(&O::ny, "mesh.ny", "Elements along the quarter's height.", 1, 2000),
        option(&O::grading, "mesh.grading",
               "First (y = 0) over last (at the grip) element height, > 0; 1 = uniform, < 1 refines toward\n"
               "the grip where the clamp makes the field steep.",
               0, 1e3),
        option(&O::grading_x, "mesh.grading_x",
               "First (x = 0) over last (at the side edge) element width, > 0; 1 = uniform, < 1 refines toward\n"
               "the side edge (the rig's guide).",
               0, 1e3)};
  }
  /// Throws InputError naming `mesh.<field>` when out of range.
  void validate() const;
};

Mesh make_quarter_mesh(const MeshOptions& options);

}  // namespace tricot::fem
