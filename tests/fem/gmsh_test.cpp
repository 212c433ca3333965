// Gmsh meshes (docs/theory.md §6): a .geo meshed at run time, .msh files in formats 2.2 and 4.1, ASCII and
// binary, named regions and boundaries, and the bad meshes that must be refused with one clear line.
#include "tricot/fem/gmsh.hpp"

#include <gmsh.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "testing/paths.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/element.hpp"

namespace tricot::fem {
namespace {

namespace fs = std::filesystem;
constexpr double kArea = 1e-9;  // the mesh's area against the geometry's, relative (straight sides)

// A 40 × 20 mm plate with a 4 mm hole: physical surface "sheet", curves "left", "right", "hole".
const char* kPlate = R"(
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 40, 20};
Disk(2) = {20, 10, 0, 4, 4};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
eps = 1e-6;
left() = Curve In BoundingBox{-eps, -eps, -eps, eps, 20 + eps, eps};
right() = Curve In BoundingBox{40 - eps, -eps, -eps, 40 + eps, 20 + eps, eps};
hole() = Curve In BoundingBox{16 - eps, 6 - eps, -eps, 24 + eps, 14 + eps, eps};
Physical Surface("sheet") = {3};
Physical Curve("left") = {left()};
Physical Curve("right") = {right()};
Physical Curve("hole") = {hole()};
)";

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

double area(const Mesh& m) {
  double a = 0;
  for (int e = 0; e < m.elements(); ++e) {
    const ElementGeometry g = element_geometry(m, e);
    for (int q = 0; q < g.points; ++q) a += g.dA0[q];
  }
  return a;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Gmsh, AGeoIsMeshedInT3AndT6WithItsNamedBoundaries) {
  const fs::path dir = test::scratch_dir("gmsh_geo");
  const fs::path geo = write(dir, "plate.geo", kPlate);
  for (int order : {1, 2}) {
    GeometryMeshOptions o;
    o.size = 2;
    o.order = order;
    const Mesh m = mesh_geometry(geo.string(), o);
    EXPECT_EQ(m.type, order == 1 ? ElementType::T3 : ElementType::T6);
    for (const char* name : {"left", "right", "hole"}) EXPECT_GT(m.boundary(name).size(), 3u) << name;
    for (int n : m.boundary("left")) EXPECT_NEAR(m.X(0, n), 0, 1e-12);
    for (int n : m.boundary("right")) EXPECT_NEAR(m.X(0, n), 40, 1e-12);
    for (int n : m.boundary("hole")) EXPECT_NEAR((m.X.col(n) - Vec2(20, 10)).norm(), 4, 1e-9);
    ASSERT_EQ(m.region_names.size(), 1u);
    EXPECT_EQ(m.region_names[0], "sheet");
    // The polygonal hole of straight T3 sides holds less than the disk; T6 sides follow it closer.
    const double exact = 40 * 20 - M_PI * 16;
    EXPECT_NEAR(area(m), exact, (order == 1 ? 5e-3 : 5e-5) * exact) << "order " << order;
  }
  GeometryMeshOptions quads;
  quads.size = 2, quads.order = 2, quads.quads = true;
  EXPECT_EQ(mesh_geometry(geo.string(), quads).type, ElementType::Q8);
}

TEST(Gmsh, MshFilesInFormats22And41AsciiAndBinaryGiveTheSameMesh) {
  const fs::path dir = test::scratch_dir("gmsh_msh");
  const fs::path geo = write(dir, "plate.geo", kPlate);
  GeometryMeshOptions o;
  o.size = 3, o.order = 2;
  const Mesh meshed = mesh_geometry(geo.string(), o);
  for (const double version : {2.2, 4.1})
    for (const int binary : {0, 1}) {
      const fs::path msh = dir / ("plate_" + std::to_string(version) + "_" + std::to_string(binary) + ".msh");
      gmsh::initialize(0, nullptr, false);
      gmsh::option::setNumber("General.Terminal", 0);
      gmsh::open(geo.string());
      gmsh::option::setNumber("Mesh.MeshSizeMax", 3);
      gmsh::model::mesh::generate(2);
      gmsh::model::mesh::setOrder(2);
      gmsh::option::setNumber("Mesh.MshFileVersion", version);
      gmsh::option::setNumber("Mesh.Binary", binary);
      gmsh::write(msh.string());
      gmsh::finalize();
      const Mesh m = read_gmsh(msh.string());
      SCOPED_TRACE(msh.filename().string());
      EXPECT_EQ(m.type, ElementType::T6);
      EXPECT_EQ(m.nodes(), meshed.nodes());
      EXPECT_EQ(m.elements(), meshed.elements());
      EXPECT_NEAR(area(m), area(meshed), kArea * area(meshed));
      for (const char* name : {"left", "right", "hole"})
        EXPECT_EQ(m.boundary(name).size(), meshed.boundary(name).size());
    }
}

// A .msh 2.2 file by hand: `elements` lines after the node block of a unit square's 5 nodes.
std::string msh22(const std::string& nodes, const std::string& elements, int element_count) {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + nodes + "$EndNodes\n$Elements\n" +
         std::to_string(element_count) + "\n" + elements + "$EndElements\n";
}
const std::string kFiveNodes = "5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 3 3 0\n";

TEST(Gmsh, BadMeshesAreRefusedWithOneLineNamingTheFile) {
  const fs::path dir = test::scratch_dir("gmsh_bad");
  // Two triangles of the square, and a third whose three nodes lie on a line (degenerate).
  const fs::path flat =
      write(dir, "flat.msh", msh22(kFiveNodes, "1 2 2 1 1 1 2 3\n2 2 2 1 1 1 3 4\n3 2 2 1 1 1 3 5\n", 3));
  const std::string e1 = error_of([&] { read_gmsh(flat.string()); });
  EXPECT_NE(e1.find("flat.msh"), std::string::npos) << e1;
  EXPECT_NE(e1.find("inverted or degenerate"), std::string::npos) << e1;
  // A triangle that shares no node with the others: two pieces.
  const std::string six = "6\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 5 5 0\n5 6 5 0\n6 6 6 0\n";
  const fs::path pieces = write(dir, "pieces.msh", msh22(six, "1 2 2 1 1 1 2 3\n2 2 2 1 1 4 5 6\n", 2));
  const std::string e2 = error_of([&] { read_gmsh(pieces.string()); });
  EXPECT_NE(e2.find("more than one piece"), std::string::npos) << e2;
  // A 9-node quadrangle (Gmsh type 10): Gmsh writes it, tricot does not take it.
  const std::string nine = "9\n1 0 0 0\n2 2 0 0\n3 2 2 0\n4 0 2 0\n5 1 0 0\n6 2 1 0\n7 1 2 0\n8 0 1 0\n9 1 1 0\n";
  const fs::path q9 = write(dir, "q9.msh", msh22(nine, "1 10 2 1 1 1 2 3 4 5 6 7 8 9\n", 1));
  const std::string e3 = error_of([&] { read_gmsh(q9.string()); });
  EXPECT_NE(e3.find("which tricot does not take"), std::string::npos) << e3;
  EXPECT_NE(e3.find("mesh.file"), std::string::npos) << e3;
  // A tetrahedron: a 3-D mesh.
  const fs::path tet =
      write(dir, "tet.msh", msh22("4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", "1 4 2 1 1 1 2 3 4\n", 1));
  const std::string e4 = error_of([&] { read_gmsh(tet.string()); });
  EXPECT_NE(e4.find("a 3-D mesh"), std::string::npos) << e4;
  // A missing file is a FileError (exit 3).
  EXPECT_THROW(read_gmsh((dir / "none.msh").string()), FileError);
}

TEST(Gmsh, ClockwiseElementsAreTurnedCounterClockwise) {
  const fs::path dir = test::scratch_dir("gmsh_cw");
  const fs::path cw = write(dir, "cw.msh", msh22(kFiveNodes, "1 2 2 1 1 1 3 2\n2 2 2 1 1 1 4 3\n", 2));
  const Mesh m = read_gmsh(cw.string());
  EXPECT_NEAR(area(m), 1.0, 1e-14);
  for (int e = 0; e < m.elements(); ++e) EXPECT_GT(element_geometry(m, e).min_detJ0, 0);
}

}  // namespace
}  // namespace tricot::fem
