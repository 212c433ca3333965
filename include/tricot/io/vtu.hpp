// VTK XML UnstructuredGrid files (.vtu) that ParaView and meshio open, and the ParaView
// collection (.pvd) that makes a time series of them. The writer takes plain arrays so that io does
// not depend on fem: the caller turns its mesh and fields into a VtuGrid.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tricot::io {

/// VTK cell type ids (vtkCellType.h) for the elements tricot uses.
enum class VtkCell : int {
  quad = 9,                 ///< 4 corners, counter-clockwise
  quadratic_quad = 23,      ///< 4 corners, then the mid-side nodes of edges 0-1, 1-2, 2-3, 3-0
  triangle = 5,             ///< 3 corners, counter-clockwise
  quadratic_triangle = 22,  ///< 3 corners, then the mid-side nodes of edges 0-1, 1-2, 2-0
};
/// Nodes of one cell: 4, 8, 3 or 6.
int vtk_nodes(VtkCell type);

/// A named field: `components` values per point (or cell), stored point after point.
struct VtuField {
  std::string name;
  int components = 1;  ///< 1 scalar, 3 vector, 9 tensor (row-major 3×3), any other count is allowed
  std::vector<double> values;
};

/// An unstructured grid with one cell type.
struct VtuGrid {
  std::vector<double> points;  ///< x, y, z per point
  VtkCell cell_type = VtkCell::quad;
  std::vector<int> connectivity;  ///< vtk_nodes(cell_type) point indices per cell, VTK's node order
  std::vector<VtuField> point_data;
  std::vector<VtuField> cell_data;
  /// Values of the whole dataset (VTK's <FieldData>, written as text; ParaView's "Field Data", meshio's
  /// field_data), e.g. a run's settings: `values.size()` tuples of one component each.
  std::vector<VtuField> field_data;

  std::size_t point_count() const { return points.size() / 3; }
  std::size_t cell_count() const;
  /// Throws std::invalid_argument when the arrays disagree (a programming error, not bad input):
  /// points not a multiple of 3, a connectivity entry out of range, a field of the wrong size, or a
  /// non-finite coordinate.
  void check() const;
};

/// How the arrays are stored.
enum class VtuFormat {
  binary,  ///< little-endian arrays, zlib-compressed (vtkZLibDataCompressor, one block), base64: the default
  ascii,   ///< decimal text, shortest round-trip digits: for reading by eye or diffing
};

/// The .vtu file's text. Non-finite field values are written as NaN (readers accept it). Both formats
/// give a reader the same doubles back.
std::string to_vtu(const VtuGrid& grid, VtuFormat format = VtuFormat::binary);
/// Writes the grid atomically (io::write_atomic). Throws FileError when it cannot be written.
void write_vtu(const std::filesystem::path& path, const VtuGrid& grid, VtuFormat format = VtuFormat::binary);

/// One entry of a ParaView collection: a data set file (relative to the .pvd) at a time value.
struct PvdEntry {
  double time = 0;
  std::string file;
};
/// Writes a .pvd collection atomically, so that ParaView opens a whole series as one time-dependent
/// data set.
void write_pvd(const std::filesystem::path& path, const std::vector<PvdEntry>& entries);

}  // namespace tricot::io
