// The case file of `tricot simulate` (and the shared part of synth's and identify's files): the
// specimen's mesh, the material law, the solver and the list of tests (docs/theory.md §5–§6). Each table is a
// function returning its io::SectionSpec, so that another verb's schema can add its own tables beside
// them; the builders turn validated tables into the engines' value types. Every check that spans keys
// goes through io::Node::fail, so errors read `FILE:LINE: KEY: problem (got V, expected R)`.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "tricot/fem/law.hpp"
#include "tricot/fem/mesh.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/wrinkling.hpp"
#include "tricot/fem/rig.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/spec.hpp"

namespace tricot::project {

/// `[mesh]`: the specimen (full size, mm) and its structured quarter mesh.
io::SectionSpec mesh_section();
/// `[law]`: `type` picks one of the sub-tables `[law.mooney_rivlin]`, `[law.neo_hookean]`,
/// `[law.corotational]`, `[law.response_surface]`, `[law.reference_fabric]`; the others are ignored,
/// so a file may keep several laws and switch by `type` alone.
io::SectionSpec law_section();
/// `[solver]`: Newton tolerances, line search, cutbacks (fem::SolveOptions).
io::SectionSpec solver_section();
/// `[[test]]`: one test (kind, material angle, grip, side edge, step list, optional `[test.mesh]`).
io::SectionSpec test_section();
/// The whole case file: [mesh], [law], [solver], [rig] and [[test]].
io::SectionSpec case_schema();

/// `[rig]`: the biaxial-induced fixture shared by every test of kind = "rig" (fem::RigOptions).
io::SectionSpec rig_section();

/// What a test does (`kind` in `[[test]]`).
enum class TestKind {
  uniaxial,      ///< grip on top, side edge free (clamped grip by default: a non-uniform field)
  biaxial,       ///< grip on top, side edge on a guide (the paper's biaxial-induced test)
  homogeneous,   ///< sliding grip, side free or guided: a uniform field (closed-form checks)
  simple_shear,  ///< no FE solve: the law at F = [[1, γ], [0, 1]] for γ in the step list (docs/theory.md §4)
  rig,           ///< the paper's rig (fem/rig.hpp): clips, tied guides short of the clips, [rig]
  custom,        ///< any mesh ([mesh] file, geometry or generator) with [[test.boundary]] conditions
};
TestKind test_kind(const io::Node& test);

// ---------------------------------------------------------------------------------------------------
// Typed specs: one struct per table, its fields the table's TOML keys, read from a validated io::Node
// (from_config) or built in code. An engine's keys are declared by its options (core/options.hpp:
// fem::MeshOptions, fem::SolveOptions, fem::RigOptions, fem::WrinklingOptions), which a spec holds as
// the engine takes them; the schema is generated from them. Ranges are the engines': each spec's one
// check builds the engine's value and calls its validate(), whose key (`mesh.nx`, `test.loads`,
// `rig.guide_gap`, `solver.tolerance`, `law.reference_fabric.k_C`) names the table and the key, so the
// error is placed at the table's Origin. Checks that span keys and that no engine makes are made here, once.

/// `[mesh]`: the generator's options as the engine takes them (nx, ny, element, grading, grading_x:
/// fem::MeshOptions::keys()) with the full specimen's sizes (mm; the quarter model is half of each), or
/// a Gmsh mesh of any specimen (`file` or `geometry`, for tests of kind = "custom").
struct MeshSpec : fem::MeshOptions {
  /// The full specimen's width and height. They hide fem::MeshOptions::width and height, the
  /// quarter's, which the mesh of each test sets to half of these (TestSpec::mesh_options).
  double width = 110;
  double height = 110;
  std::string file;      ///< a Gmsh .msh file (relative to the config file's folder), or ""
  std::string geometry;  ///< a Gmsh .geo file meshed at run time with `size` and `element`, or ""
  double size = 0;       ///< largest element size of a meshed geometry, mm; 0 = the .geo's sizes
  bool whole = false;    ///< custom tests on the generator: the whole rectangle centred on the origin
  std::string folder;    ///< the config file's folder, for relative paths
  Origin origin{"mesh"};

  /// The keys of [mesh] besides the generator's (core/options.hpp).
  static auto keys() {
    using O = MeshSpec;
    return std::tuple{
        option(&O::width, "mesh.width", "Full specimen width across the load (x), mm, > 0.", 0, 1e5),
        option(&O::height, "mesh.height", "Full free length of the specimen between the grips (y), mm, > 0.", 0, 1e5),
        option(&O::file, "mesh.file",
               "A Gmsh mesh file (.msh, formats 2.2 and 4.1, ASCII or binary), relative to this file's folder;\n"
               "kind = \"custom\" tests only. Its element type (T3, T6, Q4 or Q8) replaces `element`."),
        option(&O::geometry, "mesh.geometry",
               "A Gmsh geometry (.geo), relative to this file's folder, meshed at run time with `size` and\n"
               "`element`; kind = \"custom\" tests only."),
        option(&O::size, "mesh.size", "Largest element size of a meshed `geometry`, mm; 0 = the sizes the .geo sets.",
               0, 1e5),
        option(&O::whole, "mesh.whole",
               "kind = \"custom\" tests on the generator's mesh: the whole width × height rectangle centred on\n"
               "the origin (nx × ny elements, edges named as the quarter's), instead of the quarter [0, width/2] ×\n"
               "[0, height/2]. A full specimen whose clamps are driven by their measured motion (tricot "
               "experiment's\nmodel = \"full\").")};
  }

  static MeshSpec from_config(const io::Node& mesh);
  /// True when the mesh comes from a Gmsh file or geometry.
  bool from_gmsh() const { return !file.empty() || !geometry.empty(); }
  /// The mesh of `file` or `geometry` (read or meshed by Gmsh, checked: fem::read_gmsh). Throws
  /// InputError / FileError naming the file and `mesh.file` or `mesh.geometry`.
  fem::Mesh gmsh_mesh() const;
  /// The regions of the Gmsh mesh (physical surfaces, Mesh::region_names); none for a generated mesh.
  std::vector<std::string> region_names() const;
};

/// `[test.mesh]`: a non-zero (non-empty) value replaces the key of [mesh].
struct TestMeshSpec {
  double width = 0;
  double height = 0;
  std::string element;
  int nx = 0;
  int ny = 0;
  double grading = 0;
  double grading_x = 0;
  Origin origin{"test.mesh"};

  /// The keys of [test.mesh] (core/options.hpp): [mesh]'s, where 0 or "" keeps [mesh]'s value.
  static auto keys() {
    using O = TestMeshSpec;
    return std::tuple{
        option(&O::width, "test.mesh.width", "Full specimen width, mm; 0 = as in [mesh].", 0, 1e5),
        option(&O::height, "test.mesh.height", "Full free length between the grips, mm; 0 = as in [mesh].", 0, 1e5),
        option(&O::element, "test.mesh.element", "Q4, Q8, T3 or T6; \"\" = as in [mesh]."),
        option(&O::nx, "test.mesh.nx", "Elements across the quarter's width; 0 = as in [mesh].", 0, 2000),
        option(&O::ny, "test.mesh.ny", "Elements along the quarter's height; 0 = as in [mesh].", 0, 2000),
        option(&O::grading, "test.mesh.grading", "First over last element height; 0 = as in [mesh].", 0, 1e3),
        option(&O::grading_x, "test.mesh.grading_x", "First over last element width; 0 = as in [mesh].", 0, 1e3)};
  }

  static TestMeshSpec from_config(const io::Node& mesh);
  /// The mesh of the test: `mesh` with this table's keys in place, validated (fem::MeshOptions).
  fem::MeshOptions options(const MeshSpec& mesh) const;
};

/// `[law.mooney_rivlin]` (paper eq. 7).
struct MooneyRivlinSpec {
  io::Strings terms;  ///< C<i><j>; default: the paper's validation set
  io::Reals values;   ///< N/mm, one per term
  double kappa = 0;   ///< > 0: compressible (fem::CompressibleMooneyRivlin)
  std::string kinematics = "plane_stress";
  Origin origin{"law.mooney_rivlin"};
  MooneyRivlinSpec();
};
/// `[law.neo_hookean]`.
struct NeoHookeanSpec {
  double mu = 0.1;
  double lambda = 0.2;
  /// E and ν when given (both, and neither mu nor lambda): the law's coefficients are then (E, ν).
  std::optional<double> E, nu;
  std::string kinematics = "plane_stress";  ///< plane_stress or plane_strain
  Origin origin{"law.neo_hookean"};
};
/// `[law.corotational]` (docs/theory.md §4).
struct CorotationalSpec {
  std::string moduli = "isotropic";  ///< isotropic (G, K) or orthotropic (D11, D22, D12, D66)
  double G = 1, K = 2;
  double D11 = 1, D22 = 0.5, D12 = 0.1, D66 = 0.05;
  Origin origin{"law.corotational"};
};
/// `[law.response_surface]` (paper eqs. 8/10, docs/theory.md §5).
struct ResponseSurfaceSpec {
  std::string preset = "paper14";  ///< paper14, paper24 or general
  io::Reals coefficients;          ///< [] = all zero
  io::Strings course{"C1", "C2", "W1"};
  io::Strings wale{"W1", "W2", "C1"};
  double shear_stiffness = 0.01;
  Origin origin{"law.response_surface"};
};
/// `[law.reference_fabric]`: the parameters' names are the keys (k_C … s_J, G_s).
struct ReferenceFabricSpec : fem::ReferenceFabricParameters {
  Origin origin{"law.reference_fabric"};
};

/// `[law]`: `type` picks the sub-table.
struct LawSpec {
  std::string type = "mooney_rivlin";
  MooneyRivlinSpec mooney_rivlin;
  NeoHookeanSpec neo_hookean;
  CorotationalSpec corotational;
  ResponseSurfaceSpec response_surface;
  ReferenceFabricSpec reference_fabric;
  /// `wrinkling`: wrap the law in a tension-field membrane (fem::WrinklingLaw: taut, wrinkled, slack).
  bool wrinkling = false;
  /// `residual_stiffness` and `wrinkle_smoothing` (fem::WrinklingOptions::keys()): the membrane's
  /// options, only with `wrinkling`.
  fem::WrinklingOptions wrinkling_options;
  /// `[[law.region]]`: the laws of named regions (Gmsh physical surfaces), each a whole law table
  /// with its `name`; the regions none names keep this law (fem::RegionLaws).
  std::vector<LawSpec> region;
  std::string name;  ///< a [[law.region]]'s region
  Origin origin{"law"};

  static LawSpec from_config(const io::Node& law);
  /// The law of `type`: the law's constructor is the one check of its coefficients; its error
  /// (`law.<sub-table>.<key>`, fem/law.hpp) is placed at the sub-table's key. Throws InputError.
  /// Wrapped in fem::WrinklingLaw when `wrinkling`. With [[law.region]] tables, a fem::RegionLaws over
  /// the mesh's regions `mesh_regions` (Mesh::region_names), each name checked against them.
  std::unique_ptr<fem::Law> law(const std::vector<std::string>& mesh_regions = {}) const;
  /// The law of `type` alone (never wrapped).
  std::unique_ptr<fem::Law> inner_law() const;
  /// The law of `type`, wrapped when `wrinkling`: this table's own law, without its regions.
  std::unique_ptr<fem::Law> region_law() const;
  /// From the handler of `e`: rethrows a law's error (`law.<key>` or `law.<sub-table>.<key>`, named
  /// relative to its law table: fem/law.hpp) at that key of this table or of its sub-table; any other
  /// error unchanged.
  [[noreturn]] void rethrow(const InputError& e) const;
};

/// `[solver]`: fem::SolveOptions as the engine takes them (its keys: SolveOptions::keys()).
struct SolverSpec : fem::SolveOptions {
  Origin origin{"solver"};

  static SolverSpec from_config(const io::Node& solver);
  fem::SolveOptions options() const;  ///< validated
};

/// `[rig]`: the fixture of kind = "rig" tests, fem::RigOptions as the engine takes them (its keys:
/// RigOptions::keys(); fractions of the quarter). The options that are not [rig]'s are each test's
/// (TestSpec::model sets them).
struct RigSpec : fem::RigOptions {
  Origin origin{"rig"};

  static RigSpec from_config(const io::Node& rig);
};

/// `[[test.boundary]]`: the conditions of one named boundary of a test of kind = "custom".
struct BoundarySpec {
  std::string name;       ///< a boundary of the mesh (a Gmsh physical curve or point; "left", … of [mesh])
  io::Strings fix;        ///< components held at 0: "x", "y"
  bool symmetry = false;  ///< a line of symmetry x = const or y = const: its normal component held
  io::Reals ux, uy;       ///< prescribed displacement per step, mm (any sign, holds, unloading)
  std::string series;     ///< a CSV whose columns ux_column / uy_column give ux / uy per step, or ""
  std::string ux_column, uy_column;
  std::string force;          ///< "x" or "y": this boundary's resultant along it is the test's force, or ""
  bool proportional = false;  ///< ux, uy are mm per mm of the node's x, y (fem::BoundaryCondition::proportional)
  double tie = 0;             ///< > 0: the table's components held by ties, N/mm per mm (fem::BoundaryCondition::tie)
  io::Reals tie_end;          ///< [x, y] where the tie ends, mm, or empty
  double tie_taper = 0;       ///< mm over which the tie falls to zero before tie_end
  std::string tie_lumping = "consistent";  ///< or "segments" (fem::BoundaryCondition::tie_consistent)
  std::string folder;                      ///< the config file's folder, for `series`
  Origin origin{"test.boundary"};

  static BoundarySpec from_config(const io::Node& boundary);
};

/// `[[test]]`. An unset optional takes the kind's default.
struct TestSpec {
  std::string name = "uniaxial";
  std::string kind = "uniaxial";  ///< uniaxial, biaxial, homogeneous, simple_shear or rig
  double material_angle = 0;
  std::string control = "displacement";
  std::optional<bool> grip_holds_x;  ///< default true (a clamp); homogeneous: false
  bool grip_follows_guide = false;
  /// free or guide (FE kinds; default: guide for biaxial, else free); the full specimen side in mm
  /// for kind = "rig" (default: [mesh] width).
  std::optional<std::variant<std::string, double>> side;
  io::Reals guide;
  io::Reals loads;
  /// load_max or steps written in the file: a uniform list asked for. Neither, nor `loads`: identify
  /// reads the loads from the experiment's forces.csv (issue 29: written once).
  bool uniform_loads_given = false;
  double load_max = 10;
  int steps = 10;
  // kind = "rig" (fem::RigOptions):
  std::string pull = "wale";     ///< wale (material_angle 0) or course (90)
  double transverse_strain = 0;  ///< Green–Lagrange strain set across the pull, then held
  double pull_strain = 0.5;      ///< Green–Lagrange strain along the pull at the last step
  TestMeshSpec mesh;
  std::vector<BoundarySpec> boundary;  ///< kind = "custom": the conditions per named boundary
  double force_scale = 1;              ///< kind = "custom": force = force_scale × the boundary's resultant
  io::Reals fit_steps;                 ///< identify: the steps to fit (1-based), empty = all
  Origin origin{"test"};

  static TestSpec from_config(const io::Node& test);
  TestKind test_kind() const;
  /// kind = "custom": the [mesh] (Gmsh or generated) with the [[test.boundary]] conditions, validated.
  fem::TestModel custom_model(const MeshSpec& case_mesh) const;
  /// The test's mesh (for a rig: side/2 square with [mesh]'s elements and gradings), validated.
  fem::MeshOptions mesh_options(const MeshSpec& case_mesh) const;
  /// The FE model (simple_shear: one unit element whose loads are the γ values), validated: fem's
  /// own checks, each placed at the key of the table it names. Throws InputError.
  fem::TestModel model(const MeshSpec& case_mesh, const RigSpec& rig) const;
};

/// The whole case: [mesh], [law], [solver], [rig], [[test]].
struct CaseSpec {
  MeshSpec mesh;
  LawSpec law;
  SolverSpec solver;
  RigSpec rig;
  std::vector<TestSpec> test;
  Origin origin;

  static CaseSpec from_config(const io::Node& root);
  /// At least one test, names unique and usable as folder names.
  void check_tests() const;
  /// Every test's model, in order (each validated).
  std::vector<fem::TestModel> models() const;
  /// The test named `name`, or nullptr.
  const TestSpec* find_test(const std::string& name) const;
};

// Builders from a validated node (each reads the table into its spec and builds from that).

/// The mesh of a test: `[mesh]`, with the keys that `[test.mesh]` sets (non-zero, non-empty) in place.
fem::MeshOptions build_mesh_options(const io::Node& mesh, const io::Node* test_mesh = nullptr);
/// A test model from its `[[test]]` table, the case's `[mesh]` and (for kind = "rig") `[rig]`.
fem::TestModel build_test(const io::Node& test, const io::Node& mesh, const io::Node* rig = nullptr);
/// The law of `[law]`. Throws InputError located at the offending key.
std::unique_ptr<fem::Law> build_law(const io::Node& law);
fem::SolveOptions build_solver(const io::Node& solver);

/// Checks the list of tests of a case: at least one, names unique and usable as folder names.
void check_tests(const io::Node& root);

}  // namespace tricot::project
