// Meshes from Gmsh (docs/theory.md §6): a mesh file (.msh, formats 2.2 and 4.1, ASCII or binary) read, or a
// geometry (.geo) meshed at run time, through Debian's libgmsh. Physical surfaces name the regions,
// physical curves and points the boundaries (Mesh::boundaries); lengths are in mm.
#pragma once

#include <string>

#include "tricot/fem/mesh.hpp"

namespace tricot::fem {

/// How a .geo geometry is meshed.
struct GeometryMeshOptions {
  /// Largest element size, mm (> 0), or 0 for the sizes the .geo sets (Gmsh's Mesh.MeshSizeMax).
  double size = 0;
  int order = 1;       ///< 1 (T3, or Q4 with quads) or 2 (T6, or Q8 with quads)
  bool quads = false;  ///< recombine the triangles into quadrilaterals (Q4/Q8: Gmsh's Mesh.RecombineAll)

  /// Throws InputError naming `mesh.size`, `mesh.order`.
  void validate() const;
};

/// The 2-D mesh of a Gmsh file: its surface elements (one type: T3, T6, Q4 or Q8), their nodes
/// numbered from 0 in the file's order, regions from the physical surfaces and boundaries from the
/// physical curves and points (a group without a name is named by its tag). Elements that Gmsh
/// stored clockwise are turned counter-clockwise. Throws FileError when the file is missing or Gmsh
/// cannot read it, InputError (key `mesh.file`) for a 3-D mesh, an element type tricot does not take,
/// mixed element types, and (check_mesh) an inverted or degenerate element or a mesh in pieces.
Mesh read_gmsh(const std::string& path);

/// The mesh of a .geo geometry, meshed by Gmsh with `options`; errors as read_gmsh (key `mesh.geometry`).
Mesh mesh_geometry(const std::string& path, const GeometryMeshOptions& options);

}  // namespace tricot::fem
