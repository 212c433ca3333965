#include "tricot/io/vtu.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "tricot/io/base64.hpp"
#include "tricot/io/files.hpp"

namespace tricot::io {

int vtk_nodes(VtkCell type) {
  switch (type) {
    case VtkCell::quad: return 4;
    case VtkCell::quadratic_quad: return 8;
    case VtkCell::triangle: return 3;
    case VtkCell::quadratic_triangle: return 6;
  }
  return 0;
}

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

// One <DataArray>: `values` of a numeric type T, `components` per tuple, as text or zlib + base64.
class ArrayWriter {
 public:
  explicit ArrayWriter(VtuFormat format) : format_(format) {}

  // As text, `per_line` values a line (a tuple, or a cell's nodes).
  template <class T>
  void write(std::string& out, const char* type, const std::string& name, int components, const std::vector<T>& values,
             int per_line = 0) const {
    if (per_line == 0) per_line = components;
    out += fmt::format("        <DataArray type=\"{}\" Name=\"{}\"", type, name);
    if (components > 1) out += fmt::format(" NumberOfComponents=\"{}\"", components);
    out += fmt::format(" format=\"{}\">\n", format_ == VtuFormat::ascii ? "ascii" : "binary");
    if (format_ == VtuFormat::ascii) {
      for (std::size_t i = 0; i < values.size(); i += per_line) {
        out += "         ";
        for (int c = 0; c < per_line; ++c) {
          out += ' ';
          out += number(static_cast<double>(values[i + c]));
        }
        out += "\n";
      }
    } else {
      out += "          ";
      out += compressed(std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)));
      out += "\n";
    }
    out += "        </DataArray>\n";
  }

 private:
  // vtkZLibDataCompressor's layout with header_type UInt64: the header [blocks, block size, last block
  // size, compressed size of each block] and the compressed bytes, each base64 on its own. One block.
  static std::string compressed(std::string_view raw) {
    static_assert(std::endian::native == std::endian::little, "the VTU files say byte_order=LittleEndian");
    uLongf size = compressBound(raw.size());
    std::string packed(size, '\0');
    if (compress2(reinterpret_cast<Bytef*>(packed.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                  raw.size(), Z_BEST_SPEED) != Z_OK)
      throw std::runtime_error("vtu: zlib could not compress an array");
    packed.resize(size);
    const std::uint64_t header[4] = {raw.empty() ? 0u : 1u, raw.size(), raw.size(), packed.size()};
    const std::size_t header_bytes = (raw.empty() ? 3 : 4) * sizeof(std::uint64_t);
    return base64(std::string_view(reinterpret_cast<const char*>(header), header_bytes)) +
           (raw.empty() ? std::string() : base64(packed));
  }

  VtuFormat format_;
};

void data_array(std::string& out, const ArrayWriter& w, const VtuField& f) {
  w.write(out, "Float64", f.name, f.components, f.values);
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

std::string to_vtu(const VtuGrid& g, VtuFormat format) {
  g.check();
  const std::size_t np = g.point_count(), nc = g.cell_count();
  const int n = vtk_nodes(g.cell_type);
  const ArrayWriter w(format);
  std::string out;
  out.reserve((format == VtuFormat::ascii ? 64 : 16) * (np + nc));
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
  if (format == VtuFormat::binary) out += " compressor=\"vtkZLibDataCompressor\"";
  out += ">\n  <UnstructuredGrid>\n";
  if (!g.field_data.empty()) {
    out += "    <FieldData>\n";
    for (const auto& f : g.field_data) {
      out += fmt::format("      <DataArray type=\"Float64\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">",
                         f.name, f.values.size());
      for (double v : f.values) out += " " + number(v);
      out += " </DataArray>\n";
    }
    out += "    </FieldData>\n";
  }
  out += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", np, nc);
  out += "      <Points>\n";
  data_array(out, w, VtuField{"Points", 3, g.points});
  out += "      </Points>\n";
  out += "      <Cells>\n";
  const std::vector<std::int64_t> connectivity(g.connectivity.begin(), g.connectivity.end());
  std::vector<std::int64_t> offsets(nc);
  for (std::size_t c = 0; c < nc; ++c) offsets[c] = static_cast<std::int64_t>((c + 1) * n);
  const std::vector<std::uint8_t> types(nc, static_cast<std::uint8_t>(g.cell_type));
  w.write(out, "Int64", "connectivity", 1, connectivity, n);
  w.write(out, "Int64", "offsets", 1, offsets);
  w.write(out, "UInt8", "types", 1, types);
  out += "      </Cells>\n";
  out += "      <PointData" + attributes(g.point_data) + ">\n";
  for (const auto& f : g.point_data) data_array(out, w, f);
  out += "      </PointData>\n";
  out += "      <CellData" + attributes(g.cell_data) + ">\n";
  for (const auto& f : g.cell_data) data_array(out, w, f);
  out += "      </CellData>\n";
  out += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

void write_vtu(const std::filesystem::path& path, const VtuGrid& grid, VtuFormat format) {
  write_atomic(path, to_vtu(grid, format));
}

void write_pvd(const std::filesystem::path& path, const std::vector<PvdEntry>& entries) {
  std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& e : entries)
    out += fmt::format("    <DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>\n", number(e.time), e.file);
  out += "  </Collection>\n</VTKFile>\n";
  write_atomic(path, out);
}

}  // namespace tricot::io
