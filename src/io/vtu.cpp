#include "tricot/io/vtu.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "tricot/io/files.hpp"

namespace tricot::io {

int vtk_nodes(VtkCell type) { return type == VtkCell::quad ? 4 : 8; }

std::size_t VtuGrid::cell_count() const { return connectivity.size() / vtk_nodes(cell_type); }

void VtuGrid::check() const {
  if (points.size() % 3 != 0) throw std::invalid_argument("vtu: points must hold x, y, z per point");
  for (double x : points)
    if (!std::isfinite(x)) throw std::invalid_argument("vtu: a point coordinate is not finite");
  const std::size_t n = vtk_nodes(cell_type);
  if (connectivity.size() % n != 0)
    throw std::invalid_argument(fmt::format("vtu: connectivity must hold {} nodes per cell", n));
  for (int c : connectivity)
    if (c < 0 || static_cast<std::size_t>(c) >= point_count())
      throw std::invalid_argument(fmt::format("vtu: connectivity entry {} is not a point index", c));
  auto check_fields = [](const std::vector<VtuField>& fields, std::size_t count, const char* what) {
    for (const auto& f : fields)
      if (f.components < 1 || f.values.size() != count * static_cast<std::size_t>(f.components))
        throw std::invalid_argument(fmt::format("vtu: {} field '{}' has {} values, expected {} × {}", what, f.name,
                                                f.values.size(), count, f.components));
  };
  check_fields(point_data, point_count(), "point");
  check_fields(cell_data, cell_count(), "cell");
}

namespace {

// Shortest text that reads back to the same double; NaN/inf as VTK's readers spell them.
std::string number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return fmt::format("{}", x);
}

void data_array(std::string& out, const VtuField& f) {
  out += fmt::format("        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
                     f.name, f.components);
  for (std::size_t i = 0; i < f.values.size(); i += f.components) {
    out += "         ";
    for (int c = 0; c < f.components; ++c) {
      out += ' ';
      out += number(f.values[i + c]);
    }
    out += "\n";
  }
  out += "        </DataArray>\n";
}

// The first field of each kind becomes ParaView's active one.
std::string attributes(const std::vector<VtuField>& fields) {
  std::string scalars, vectors, tensors;
  for (const auto& f : fields) {
    if (f.components == 1 && scalars.empty()) scalars = f.name;
    if (f.components == 3 && vectors.empty()) vectors = f.name;
    if (f.components == 9 && tensors.empty()) tensors = f.name;
  }
  std::string s;
  if (!scalars.empty()) s += " Scalars=\"" + scalars + "\"";
  if (!vectors.empty()) s += " Vectors=\"" + vectors + "\"";
  if (!tensors.empty()) s += " Tensors=\"" + tensors + "\"";
  return s;
}

}  // namespace

std::string to_vtu(const VtuGrid& g) {
  g.check();
  const std::size_t np = g.point_count(), nc = g.cell_count();
  const int n = vtk_nodes(g.cell_type);
  std::string out;
  out.reserve(64 * (np + nc));
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  out += "  <UnstructuredGrid>\n";
  out += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", np, nc);
  out += "      <Points>\n";
  data_array(out, VtuField{"Points", 3, g.points});
  out += "      </Points>\n";
  out += "      <Cells>\n";
  out += "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (std::size_t c = 0; c < nc; ++c) {
    out += "         ";
    for (int k = 0; k < n; ++k) out += fmt::format(" {}", g.connectivity[c * n + k]);
    out += "\n";
  }
  out += "        </DataArray>\n";
  out += "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n         ";
  for (std::size_t c = 0; c < nc; ++c) out += fmt::format(" {}", (c + 1) * n);
  out += "\n        </DataArray>\n";
  out += "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n         ";
  for (std::size_t c = 0; c < nc; ++c) out += fmt::format(" {}", static_cast<int>(g.cell_type));
  out += "\n        </DataArray>\n";
  out += "      </Cells>\n";
  out += "      <PointData" + attributes(g.point_data) + ">\n";
  for (const auto& f : g.point_data) data_array(out, f);
  out += "      </PointData>\n";
  out += "      <CellData" + attributes(g.cell_data) + ">\n";
  for (const auto& f : g.cell_data) data_array(out, f);
  out += "      </CellData>\n";
  out += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

void write_vtu(const std::filesystem::path& path, const VtuGrid& grid) { write_atomic(path, to_vtu(grid)); }

void write_pvd(const std::filesystem::path& path, const std::vector<PvdEntry>& entries) {
  std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& e : entries)
    out += fmt::format("    <DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>\n", number(e.time), e.file);
  out += "  </Collection>\n</VTKFile>\n";
  write_atomic(path, out);
}

}  // namespace tricot::io
