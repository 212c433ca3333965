// The experiment on disk (see experiment_files.hpp).
#include "tricot/project/experiment_files.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <type_traits>
#include <nlohmann/json.hpp>

#include "output/json.hpp"

#include "tricot/core/error.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

std::string num(double v) { return fmt::format("{:.6g}", v); }

// ---------------------------------------------------------------------------------------------------
// Writing

void write_forces(const fs::path& file, const ident::TestData& d) {
  io::Table t;
  t.columns = {"step", "load"};
  if (!d.edge_displacement.empty()) t.columns.push_back("edge_displacement");
  if (!d.edge_force.empty()) t.columns.push_back("edge_force");
  for (int k = 0; k < d.steps(); ++k) {
    std::vector<double> row{double(k + 1), d.loads[k]};
    if (!d.edge_displacement.empty()) row.push_back(d.edge_displacement[k]);
    if (!d.edge_force.empty()) row.push_back(d.edge_force[k]);
    t.rows.push_back(std::move(row));
  }
  io::write_atomic(file, io::to_csv(t));
}

void write_field(const fs::path& file, const ident::TestData& d) {
  io::Table t;
  t.columns = {"step", "id", "x", "y", "u", "v"};
  for (int k = 0; k < d.steps(); ++k)
    for (int p = 0; p < d.point_count(); ++p)
      t.rows.push_back({double(k + 1), double(d.point_ids[p]), d.points(0, p), d.points(1, p), d.u(k, p), d.v(k, p)});
  io::write_atomic(file, io::to_csv(t));
}

// ---------------------------------------------------------------------------------------------------
// Reading

// A cell of a table read by io::read_csv, for messages: FILE:LINE: COLUMN.
struct Cells {
  const io::Table& t;
  std::string file;
  Location at(std::size_t row, const std::string& column) const { return {file, t.lines.at(row), column}; }
};

// A cell that must hold an integer (step, id).
int integer_cell(const Cells& c, std::size_t row, std::size_t col) {
  const double v = c.t.rows[row][col];
  if (v != std::round(v) || std::abs(v) > 2e9)
    throw InputError(c.at(row, c.t.columns[col]), "not an integer", num(v), "an integer");
  return static_cast<int>(v);
}

// Largest |value| accepted in forces.csv and field.csv (mm, N, s, px): far beyond any specimen, and its
// square sums stay finite, so a group's RMS scale (docs/theory.md §2) cannot overflow to a zero weight.
constexpr double kLargestDatum = 1e12;

// Every cell of the table within ±kLargestDatum, or InputError at FILE:LINE: COLUMN (issue 14).
void check_magnitudes(const Cells& c) {
  for (std::size_t r = 0; r < c.t.rows.size(); ++r)
    for (std::size_t col = 0; col < c.t.rows[r].size(); ++col)
      if (!(std::abs(c.t.rows[r][col]) <= kLargestDatum))
        throw InputError(c.at(r, c.t.columns[col]), "value out of range", num(c.t.rows[r][col]),
                         "|value| <= " + num(kLargestDatum));
}

std::optional<std::size_t> find_column(const io::Table& t, const std::string& name) {
  for (std::size_t i = 0; i < t.columns.size(); ++i)
    if (t.columns[i] == name) return i;
  return std::nullopt;
}

void read_forces(const fs::path& file, ident::TestData& d) {
  const io::Table t = io::read_csv(file);
  const Cells c{t, file.string()};
  const std::size_t step = t.column("step", c.file), load = t.column("load", c.file);
  if (t.rows.empty()) throw InputError({c.file, 0, ""}, "no steps: the file has a header and no rows");
  check_magnitudes(c);
  const auto disp = find_column(t, "edge_displacement"), force = find_column(t, "edge_force");
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const int k = integer_cell(c, r, step);
    if (k != static_cast<int>(r) + 1)
      throw InputError(c.at(r, "step"), "steps must be numbered 1, 2, 3, … in order", std::to_string(k),
                       std::to_string(r + 1));
    const double L = t.rows[r][load];
    // Any path (a lab record's holds and unloading under displacement control, issue 29): the project's
    // tests must have these loads, and a force-controlled test's must increase (fem::TestModel).
    d.loads.push_back(L);
    if (disp) d.edge_displacement.push_back(t.rows[r][*disp]);
    if (force) d.edge_force.push_back(t.rows[r][*force]);
  }
}

void read_field(const fs::path& file, ident::TestData& d) {
  const io::Table t = io::read_csv(file);
  const Cells c{t, file.string()};
  const std::size_t step = t.column("step", c.file), id = t.column("id", c.file), x = t.column("x", c.file),
                    y = t.column("y", c.file), u = t.column("u", c.file), v = t.column("v", c.file);
  if (t.rows.empty()) return;  // a header only: no field data
  check_magnitudes(c);
  const int K = d.steps();

  // Points in the order of their first appearance; each (step, id) once; x, y the same at every step.
  std::map<int, int> index;  // id -> point
  std::vector<std::size_t> first_row;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const int i = integer_cell(c, r, id);
    if (index.emplace(i, static_cast<int>(first_row.size())).second) first_row.push_back(r);
  }
  const int m = static_cast<int>(first_row.size());
  d.point_ids.resize(m);
  d.points.resize(2, m);
  for (const auto& [i, p] : index) {
    d.point_ids[p] = i;
    d.points(0, p) = t.rows[first_row[p]][x];
    d.points(1, p) = t.rows[first_row[p]][y];
  }
  d.u.setConstant(K, m, std::nan(""));
  d.v.setConstant(K, m, std::nan(""));
  const auto su = find_column(t, "sigma_u"), sv = find_column(t, "sigma_v");  // tricot experiment's DIC σ
  if (su && sv) d.sigma_u.setConstant(K, m, std::nan("")), d.sigma_v.setConstant(K, m, std::nan(""));
  std::vector<std::size_t> seen(static_cast<std::size_t>(K) * m, SIZE_MAX);
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const int k = integer_cell(c, r, step);
    if (k < 1 || k > K)
      throw InputError(c.at(r, "step"), fmt::format("step out of range: {} has {} steps", kForcesFile, K),
                       std::to_string(k), fmt::format("1 to {}", K));
    const int i = integer_cell(c, r, id), p = index.at(i);
    std::size_t& s = seen[static_cast<std::size_t>(k - 1) * m + p];
    if (s != SIZE_MAX)
      throw InputError(c.at(r, "id"),
                       fmt::format("point {} appears twice at step {} (also line {})", i, k, t.lines[s]));
    s = r;
    for (auto [col, axis] : {std::pair{x, 0}, std::pair{y, 1}})
      if (t.rows[r][col] != d.points(axis, p))
        throw InputError(c.at(r, t.columns[col]),
                         fmt::format("point {} moved: its position must be the same at every step (line {})", i,
                                     t.lines[first_row[p]]),
                         num(t.rows[r][col]), num(d.points(axis, p)));
    d.u(k - 1, p) = t.rows[r][u];
    d.v(k - 1, p) = t.rows[r][v];
    if (su && sv) d.sigma_u(k - 1, p) = t.rows[r][*su], d.sigma_v(k - 1, p) = t.rows[r][*sv];
  }
  for (int k = 0; k < K; ++k)
    for (int p = 0; p < m; ++p)
      if (seen[static_cast<std::size_t>(k) * m + p] == SIZE_MAX)
        throw InputError({c.file, 0, "step"}, fmt::format("point {} has no row for step {}", d.point_ids[p], k + 1), "",
                         "every point at every step");
}

// ---------------------------------------------------------------------------------------------------
// truth.json

json sigma_json(const ident::Sigma& s) {
  return json{{"edge_displacement", s.edge_displacement}, {"edge_force", s.edge_force}, {"field", s.field}};
}

}  // namespace

void write_test_data(const fs::path& dir, const ident::TestData& d) {
  write_forces(dir / d.name / kForcesFile, d);
  if (d.has_field()) write_field(dir / d.name / kFieldFile, d);
}

ident::TestData read_test_data(const fs::path& dir, const std::string& name, ident::FieldKind kind) {
  const fs::path folder = dir / name;
  if (!fs::is_directory(folder))
    throw FileError({folder.string(), 0, ""}, "no data for test '" + name + "': folder not found", "",
                    "a folder per [[test]] of the project, as tricot synth writes");
  ident::TestData d;
  d.name = name;
  d.field_kind = kind;
  d.source = (folder / kForcesFile).string();
  read_forces(folder / kForcesFile, d);
  if (fs::exists(folder / kFieldFile)) {
    read_field(folder / kFieldFile, d);
    if (d.has_field()) d.source = (folder / kFieldFile).string();
  }
  return d;
}

ident::Experiment read_experiment(const fs::path& dir, const std::vector<std::string>& names, ident::FieldKind kind) {
  if (!fs::is_directory(dir))
    throw FileError({dir.string(), 0, ""}, "experiment folder not found", "",
                    "a folder written by tricot synth (or by hand: <test>/forces.csv, <test>/field.csv)");
  ident::Experiment e;
  for (const auto& n : names) e.tests.push_back(read_test_data(dir, n, kind));
  e.validate();
  return e;
}

const Truth::Test* Truth::find(const std::string& name) const {
  for (const auto& t : tests)
    if (t.name == name) return &t;
  return nullptr;
}

std::optional<double> Truth::value(const std::string& name) const {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return values[k];
  return std::nullopt;
}

void write_truth(const fs::path& dir, const Truth& t) {
  json j;
  j["law"] = t.law;
  json c = json::object();
  for (std::size_t k = 0; k < t.names.size(); ++k) c[t.names[k]] = t.values[k];
  j["coefficients"] = c;
  j["noise_relative"] = t.noise_relative;
  j["seed"] = t.seed;
  j["field_kind"] = ident::to_string(t.field_kind);
  json tests = json::array();
  for (const auto& s : t.tests) {
    tests.push_back({{"name", s.name},
                     {"control", s.control},
                     {"mesh",
                      {{"element", fem::to_string(s.mesh.type)},
                       {"width", 2 * s.mesh.width},
                       {"height", 2 * s.mesh.height},
                       {"nx", s.mesh.nx},
                       {"ny", s.mesh.ny},
                       {"grading", s.mesh.grading},
                       {"dofs", s.dofs}}},
                     {"steps", s.steps},
                     {"points", s.points},
                     {"dropped_points", s.dropped_points},
                     {"sigma", sigma_json(s.sigma)}});
  }
  j["tests"] = tests;
  io::write_atomic(dir / kTruthFile, j.dump(2) + "\n");
}

std::optional<Truth> read_truth(const fs::path& dir) {
  const fs::path path = dir / kTruthFile;
  if (!fs::exists(path)) return std::nullopt;
  const std::string file = path.string();
  json j;
  try {
    j = json::parse(io::read_text(path));
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number that overflows
    throw InputError({file, 0, ""}, "not valid JSON: " + json_problem(e));
  }
  Truth t;
  t.law = json_get<std::string>(j, "law", file, "");
  const json c = j.contains("coefficients") ? j["coefficients"] : json();
  if (!c.is_object()) throw InputError({file, 0, "coefficients"}, "missing or not an object");
  for (const auto& [name, value] : c.items()) {
    if (!value.is_number()) throw InputError({file, 0, "coefficients." + name}, "not a number");
    t.names.push_back(name);
    t.values.push_back(value.get<double>());
  }
  t.noise_relative = json_get_or(j, "noise_relative", 0.0, file, "");
  t.seed = json_get_or(j, "seed", std::uint64_t{0}, file, "");
  t.field_kind = json_get_or(j, "field_kind", std::string("cumulative"), file, "") == "incremental"
                     ? ident::FieldKind::incremental
                     : ident::FieldKind::cumulative;
  if (j.contains("tests")) {
    if (!j["tests"].is_array()) throw InputError({file, 0, "tests"}, "not an array");
    for (const json& s : j["tests"]) {
      Truth::Test x;
      x.name = json_get<std::string>(s, "name", file, "tests.");
      const std::string p = "tests." + x.name + ".";
      x.control = json_get_or(s, "control", std::string(), file, p);
      x.steps = json_get_or(s, "steps", 0, file, p);
      x.points = json_get_or(s, "points", 0, file, p);
      x.dropped_points = json_get_or(s, "dropped_points", 0, file, p);
      if (s.contains("mesh")) {
        const json& m = s["mesh"];
        x.mesh.type = json_get_or(m, "element", std::string("Q8"), file, p + "mesh.") == "Q4" ? fem::ElementType::Q4
                                                                                              : fem::ElementType::Q8;
        x.mesh.width = json_get_or(m, "width", 2 * x.mesh.width, file, p + "mesh.") / 2;
        x.mesh.height = json_get_or(m, "height", 2 * x.mesh.height, file, p + "mesh.") / 2;
        x.mesh.nx = json_get_or(m, "nx", x.mesh.nx, file, p + "mesh.");
        x.mesh.ny = json_get_or(m, "ny", x.mesh.ny, file, p + "mesh.");
        x.mesh.grading = json_get_or(m, "grading", 1.0, file, p + "mesh.");
        x.dofs = json_get_or(m, "dofs", 0, file, p + "mesh.");
      }
      if (s.contains("sigma")) {
        const json& g = s["sigma"];
        x.sigma.edge_displacement = json_get<double>(g, "edge_displacement", file, p + "sigma.");
        x.sigma.edge_force = json_get<double>(g, "edge_force", file, p + "sigma.");
        x.sigma.field = json_get<double>(g, "field", file, p + "sigma.");
      }
      t.tests.push_back(std::move(x));
    }
  }
  return t;
}

}  // namespace tricot::project
