// Gmsh meshes through libgmsh (docs/theory.md §6). Gmsh keeps one global model: every use is serialised and
// starts from a fresh session.
#include "tricot/fem/gmsh.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <unordered_map>

#include "tricot/core/error.hpp"
#include "tricot/fem/element.hpp"

namespace tricot::fem {

void GeometryMeshOptions::validate() const {
  if (!(size >= 0) || !std::isfinite(size))
    throw InputError(Location{"", 0, "mesh.size"}, "out of range", format_number(size),
                     ">= 0 mm (0 = the .geo's sizes)");
  if (order != 1 && order != 2)
    throw InputError(Location{"", 0, "mesh.order"}, "out of range", std::to_string(order), "1 or 2");
}

namespace {

std::mutex gmsh_mutex;

// One Gmsh session: initialised quiet, finalised on every way out.
struct Session {
  Session() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);
  }
  ~Session() { gmsh::finalize(); }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

// Gmsh's element type numbers.
std::optional<ElementType> from_gmsh(int type) {
  switch (type) {
    case 2: return ElementType::T3;
    case 9: return ElementType::T6;
    case 3: return ElementType::Q4;
    case 16: return ElementType::Q8;
    default: return std::nullopt;
  }
}

std::string gmsh_type_name(int type) {
  std::string name;
  int dim = 0, order = 0, nodes = 0, primary = 0;
  std::vector<double> local;
  try {
    gmsh::model::mesh::getElementProperties(type, name, dim, order, nodes, local, primary);
  } catch (const std::exception&) {
    return "type " + std::to_string(type);
  }
  return name + " (Gmsh type " + std::to_string(type) + ", " + std::to_string(nodes) + " nodes)";
}

// The element turned counter-clockwise: corners 0, k−1, …, 1 and the mid-sides reversed with them.
void reverse(ElementType type, std::array<int, 8>& c) {
  const int k = corners(type);
  std::array<int, 8> r = c;
  for (int a = 1; a < k; ++a) r[a] = c[k - a];
  if (nodes_per_element(type) > k)
    for (int a = 0; a < k; ++a) r[k + a] = c[k + (k - 1 - a)];  // edge a of the reversed element
  c = r;
}

// The loaded model as a tricot mesh; `source` and `key` name the input in errors.
Mesh from_model(const std::string& source, const std::string& key) {
  auto bad = [&](const std::string& problem, const std::string& got = {}, const std::string& expected = {}) {
    throw InputError(Location{source, 0, key}, problem, got, expected);
  };
  {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, 3);
    if (!types.empty())
      bad("a 3-D mesh (" + gmsh_type_name(types.front()) + " volume elements): tricot models membranes in a plane",
          std::to_string(tags.front().size()) + " volume elements", "a 2-D mesh in the plane z = 0");
  }

  // Surface elements, entity by entity (each entity's region from its physical surface).
  gmsh::vectorpair surfaces;
  gmsh::model::getEntities(surfaces, 2);
  std::unordered_map<int, int> region_of_entity;
  Mesh m;
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 2);
  for (const auto& [dim, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int e : entities) region_of_entity.emplace(e, static_cast<int>(m.region_names.size()));
    m.region_names.push_back(name.empty() ? std::to_string(tag) : name);
  }

  std::optional<int> gmsh_type;
  std::vector<std::size_t> element_nodes;  // node tags, nodes_per_element per element
  std::vector<int> region;
  for (const auto& [dim, entity] : surfaces) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, 2, entity);
    for (size_t i = 0; i < types.size(); ++i) {
      if (!from_gmsh(types[i]))
        bad("Gmsh writes " + gmsh_type_name(types[i]) + " elements, which tricot does not take",
            gmsh_type_name(types[i]), "T3 (2), T6 (9), Q4 (3) or Q8 (16)");
      if (gmsh_type && *gmsh_type != types[i])
        bad("the mesh mixes element types", gmsh_type_name(*gmsh_type) + " and " + gmsh_type_name(types[i]),
            "one type (recombine all surfaces, or none)");
      gmsh_type = types[i];
      element_nodes.insert(element_nodes.end(), nodes[i].begin(), nodes[i].end());
      const auto it = region_of_entity.find(entity);
      const int r = it == region_of_entity.end() ? -1 : it->second;
      region.insert(region.end(), tags[i].size(), r);
    }
  }
  if (!gmsh_type) bad("the file has no surface elements", "none", "a 2-D mesh of T3, T6, Q4 or Q8 elements");
  m.type = *from_gmsh(*gmsh_type);
  const int per = nodes_per_element(m.type);

  // Nodes: those of the surface elements, numbered in the order of their tags.
  std::vector<std::size_t> node_tags;
  std::vector<double> coord, parametric;
  gmsh::model::mesh::getNodes(node_tags, coord, parametric, -1, -1, false, false);
  std::vector<std::size_t> used(element_nodes);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::unordered_map<std::size_t, int> index;
  for (std::size_t t : used) index.emplace(t, static_cast<int>(index.size()));
  m.X.resize(2, static_cast<Eigen::Index>(used.size()));
  double extent = 0;
  for (size_t i = 0; i < node_tags.size(); ++i)
    extent = std::max({extent, std::abs(coord[3 * i]), std::abs(coord[3 * i + 1])});
  for (size_t i = 0; i < node_tags.size(); ++i) {
    const auto it = index.find(node_tags[i]);
    if (it == index.end()) continue;
    if (std::abs(coord[3 * i + 2]) > 1e-9 * std::max(extent, 1.0))
      bad("node " + std::to_string(node_tags[i]) + " is out of the plane z = 0: a 3-D surface",
          "z = " + format_number(coord[3 * i + 2]), "a 2-D mesh in the plane z = 0");
    m.X.col(it->second) = Vec2(coord[3 * i], coord[3 * i + 1]);
  }

  // Elements, counter-clockwise.
  const size_t ne = element_nodes.size() / per;
  m.connectivity.resize(ne);
  for (size_t e = 0; e < ne; ++e) {
    m.connectivity[e].fill(-1);
    for (int a = 0; a < per; ++a) m.connectivity[e][a] = index.at(element_nodes[e * per + a]);
  }
  for (size_t e = 0; e < ne; ++e) {
    // Clockwise = every quadrature point's det < 0 (a tangled or flat element keeps its order and
    // fails check_mesh).
    const ElementGeometry g = element_geometry(m, static_cast<int>(e));
    bool clockwise = true;
    for (int q = 0; q < g.points; ++q) clockwise = clockwise && g.dA0[q] < 0;
    if (clockwise) reverse(m.type, m.connectivity[e]);
  }
  if (!m.region_names.empty()) {
    if (std::count(region.begin(), region.end(), -1) > 0) {
      for (int& r : region)
        if (r < 0) r = static_cast<int>(m.region_names.size());
      m.region_names.push_back("unnamed");
    }
    m.region = std::move(region);
  }

  // Boundaries: physical curves and points.
  for (int dim : {1, 0}) {
    gmsh::vectorpair named;
    gmsh::model::getPhysicalGroups(named, dim);
    for (const auto& [d, tag] : named) {
      std::string name;
      gmsh::model::getPhysicalName(d, tag, name);
      if (name.empty()) name = std::to_string(tag);
      std::vector<std::size_t> tags;
      std::vector<double> xyz;
      gmsh::model::mesh::getNodesForPhysicalGroup(d, tag, tags, xyz);
      std::vector<int>& nodes = m.boundaries[name];
      for (std::size_t t : tags)
        if (const auto it = index.find(t); it != index.end()) nodes.push_back(it->second);
      std::sort(nodes.begin(), nodes.end());
      nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    }
  }
  check_mesh(m, source);
  return m;
}

void require_file(const std::string& path, const std::string& key) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw FileError(Location{path, 0, key}, "mesh file not found or not a file", "\"" + path + "\"",
                    "an existing .msh or .geo file");
}

// Runs `body` in a fresh Gmsh session; Gmsh's own errors become a FileError naming the file.
template <typename Body>
Mesh with_gmsh(const std::string& path, const std::string& key, Body body) {
  require_file(path, key);
  std::lock_guard<std::mutex> lock(gmsh_mutex);
  Session session;
  try {
    return body();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    std::string why = e.what();
    std::string last;
    try {
      gmsh::logger::getLastError(last);
    } catch (...) {}
    if (!last.empty()) why = last;
    throw FileError(Location{path, 0, key}, "Gmsh cannot read it: " + why);
  } catch (const std::string& why) {  // libgmsh's API throws its last error as a string
    throw FileError(Location{path, 0, key}, "Gmsh cannot read it: " + why);
  }
}

}  // namespace

Mesh read_gmsh(const std::string& path) {
  return with_gmsh(path, "mesh.file", [&] {
    gmsh::open(path);
    return from_model(path, "mesh.file");
  });
}

Mesh mesh_geometry(const std::string& path, const GeometryMeshOptions& options) {
  options.validate();
  return with_gmsh(path, "mesh.geometry", [&] {
    gmsh::open(path);
    if (options.size > 0) gmsh::option::setNumber("Mesh.MeshSizeMax", options.size);
    if (options.quads) gmsh::option::setNumber("Mesh.RecombineAll", 1);
    gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 1);  // Q8, not Q9
    gmsh::model::mesh::generate(2);
    if (options.order == 2) gmsh::model::mesh::setOrder(2);
    return from_model(path, "mesh.geometry");
  });
}

}  // namespace tricot::fem
