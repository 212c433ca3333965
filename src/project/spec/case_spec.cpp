// The case schema and its builders (docs/theory.md §5–§6). See case_config.hpp.
#include "tricot/project/case_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <set>
#include <unistd.h>

#include "spec/schema.hpp"
#include "tricot/fem/corotational.hpp"
#include "tricot/fem/gmsh.hpp"
#include "tricot/io/files.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/compressible_mooney_rivlin.hpp"
#include "tricot/fem/neo_hookean.hpp"
#include "tricot/fem/region_laws.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/response_surface.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

namespace {

std::string num(double x) { return io::to_toml(x); }

// fem names a bad value `<table>.<key>` without a file (`mesh.nx`, `test.loads`, `rig.guide_gap`):
// rethrow it at that key of the Origin of the table it names, which may be another table of the same
// keys ([test.mesh] for [mesh], a [[test]] for test). An error already placed in a file is rethrown
// unchanged. (A law's keys are placed by LawSpec::rethrow.)
struct Tables {
  const Origin* mesh = nullptr;
  const Origin* test = nullptr;
  const Origin* rig = nullptr;
  const Origin* solver = nullptr;
};

[[noreturn]] void rethrow_fem(const InputError& e, const Tables& t) {
  if (!e.where().file.empty()) throw e;
  const std::string& k = e.where().key;
  const auto dot = k.find('.');
  const std::string table = k.substr(0, dot), key = dot == std::string::npos ? std::string() : k.substr(dot + 1);
  const Origin* o = table == "mesh"     ? t.mesh
                    : table == "test"   ? t.test
                    : table == "rig"    ? t.rig
                    : table == "solver" ? t.solver
                                        : nullptr;
  if (!o) throw e;
  throw InputError(o->where(key), problem_of(e));
}

std::string join(const Strings& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// "C2W1" -> εC² εW; "C1" -> εC; "W3" -> εW³ (a general response surface's monomials).
std::vector<fem::Monomial> monomials(const Origin& o, const Strings& names, const char* key) {
  static const std::regex pattern(R"((?:C(\d+))?(?:W(\d+))?)");
  std::vector<fem::Monomial> out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    std::smatch m;
    if (names[k].empty() || !std::regex_match(names[k], m, pattern))
      o.fail(key, fmt::format("monomial {} is not written C<p>W<q>", k + 1), "\"" + names[k] + "\"",
             "e.g. \"C2\", \"W1\", \"C1W2\"");
    out.push_back({m[1].matched ? std::stoi(m[1]) : 0, m[2].matched ? std::stoi(m[2]) : 0});
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Schema

io::SectionSpec mesh_section() {
  SectionSpec s{"mesh",
                "The specimen and its mesh. The built-in tests model a quarter of the specimen (symmetry on\n"
                "x = 0 and y = 0, docs/theory.md §6): the mesh covers width/2 × height/2 with nx × ny elements, whose\n"
                "edges are named left, bottom, top and right. Tests of kind = \"custom\" take this mesh or a\n"
                "Gmsh mesh of any specimen (`file` or `geometry`; lengths in mm), whose physical curves and\n"
                "points name the boundaries that [[test.boundary]] tables hold or pull.",
                false,
                {},
                {}};
  const MeshSpec d;
  add_keys(s, d);
  add_keys(s, static_cast<const fem::MeshOptions&>(d));
  return s;
}

namespace {

SectionSpec test_mesh_section() {
  SectionSpec s{
      "mesh", "This test's own mesh: a non-zero (non-empty) value replaces the key of [mesh].", false, {}, {}};
  add_keys(s, TestMeshSpec{});
  return s;
}

}  // namespace

io::SectionSpec law_section() {
  SectionSpec law{
      "law",
      "The material law (docs/theory.md §5). Forces are per unit reference width (N/mm): a knit's thickness\n"
      "has no meaning, so every modulus below is a membrane modulus (stress × thickness).",
      false,
      {},
      {}};
  law.keys = {
      key("type", std::string("mooney_rivlin"),
          "Which law: the table [law.<type>] below holds its coefficients; the other tables are ignored.", -kInf, kInf,
          {"mooney_rivlin", "neo_hookean", "corotational", "response_surface", "reference_fabric"}),
      key("wrinkling", false,
          "Wrap the law in a tension-field membrane (docs/theory/fabric.md §8): where a principal\n"
          "stress would be compressive the membrane wrinkles and carries a uniaxial tension along the\n"
          "wrinkles (angle and wrinkle strain from zero traction across them), or is slack where no\n"
          "direction is stretched. Taut points keep the law as it is.")};
  add_keys(law, LawSpec{}.wrinkling_options);

  SectionSpec mr{"mooney_rivlin",
                 "Mooney–Rivlin, W = Σ C_ij (I1 − 3)^i (I2 − 3)^j (paper eq. 7): incompressible in plane stress; with\n"
                 "kappa > 0 compressible, W = Σ C_ij (Ī1 − 3)^i (Ī2 − 3)^j + κ/2 (ln J)² on the isochoric invariants\n"
                 "(docs/theory.md §5.2), in plane stress or plane strain.",
                 false,
                 {},
                 {}};
  // Default: the paper's validation set (docs/validation.md §1), a rubber-like S curve.
  Strings mr_names;
  Reals mr_values;
  for (const auto& t : fem::paper_mooney_rivlin_terms()) {
    mr_names.push_back(fmt::format("C{}{}", t.i, t.j));
    mr_values.push_back(t.C);
  }
  mr.keys = {
      key("terms", mr_names, "Names C<i><j> of the terms kept (i, j = 0..9, not both 0)."),
      key("values", mr_values, "C_ij of each term, N/mm, in the order of `terms`.", -1e6, 1e6),
      key("kappa", 0.0,
          "Bulk modulus κ of the volumetric term, N/mm: 0 = incompressible; > 0 = compressible (identified\n"
          "as the coefficient \"kappa\"). At small strain μ = 2 (C10 + C01).",
          0, 1e9),
      key("kinematics", std::string("plane_stress"),
          "plane_stress (σ33 = 0) or plane_strain (C33 = 1; needs kappa > 0).", -kInf, kInf,
          {"plane_stress", "plane_strain"}),
  };
  SectionSpec nh{"neo_hookean", "Compressible neo-Hookean membrane (a helper law for tests).", false, {}, {}};
  nh.keys = {
      key("mu", 0.1, "Shear modulus μ, N/mm, > 0.", 0, 1e6),
      key("lambda", 0.2, "Lamé modulus λ, N/mm.", 0, 1e6),
      key("E", 0.0,
          "Or Young's modulus E, N/mm, with `nu` instead of mu and lambda: the law's coefficients are then\n"
          "\"E\" and \"nu\" (μ = E/(2(1 + ν)), λ = Eν/((1 + ν)(1 − 2ν)), the 3-D Lamé modulus, for either\n"
          "kinematics).",
          0, 1e9),
      key("nu", 0.0, "Poisson's ratio ν in (−1, 0.5), with `E`.", -1, 0.5),
      key("kinematics", std::string("plane_stress"),
          "plane_stress (a membrane, σ33 = 0) or plane_strain (a slice of a thick specimen, C33 = 1: then\n"
          "μ and λ are the moduli times the thickness).",
          -kInf, kInf, {"plane_stress", "plane_strain"}),
  };
  for (auto& k : nh.keys)
    if (k.name == "E" || k.name == "nu") k.alternative = true;
  SectionSpec co{"corotational",
                 "Corotational Eulerian law τ̂ = 𝔻 : ln U (docs/theory.md §4): orthotropic linear on the logarithmic\n"
                 "strain in the material frame (course, wale), or isotropic.",
                 false,
                 {},
                 {}};
  co.keys = {
      key("moduli", std::string("isotropic"), "isotropic (G, K) or orthotropic (D11, D22, D12, D66).", -kInf, kInf,
          {"isotropic", "orthotropic"}),
      key("G", 1.0, "Isotropic shear modulus, N/mm, > 0.", 0, 1e6),
      key("K", 2.0, "Isotropic areal (2-D) bulk modulus, N/mm, > 0.", 0, 1e6),
      key("D11", 1.0, "Course stiffness, N/mm, > 0.", 0, 1e6),
      key("D22", 0.5, "Wale stiffness, N/mm, > 0.", 0, 1e6),
      key("D12", 0.1, "Course–wale coupling, N/mm (D11 D22 > D12²).", -1e6, 1e6),
      key("D66", 0.05, "Shear stiffness, N/mm, > 0 (engineering shear: τ̂12 = D66 · 2 ln U_12).", 0, 1e6),
  };
  SectionSpec rs{
      "response_surface",
      "Orthotropic response surface (paper eqs. 8/10, docs/theory.md §5): forces per width along course and\n"
      "wale as polynomials of the Green–Lagrange strains εC, εW along the material axes.",
      false,
      {},
      {}};
  rs.keys = {
      key("preset", std::string("paper14"),
          "Polynomial family: paper14 (a1..a6, b1..b2, c1..c4, d1..d2), paper24 (6, 6, 6, 6) or general\n"
          "(the monomials of `course` and `wale`).",
          -kInf, kInf, {"paper14", "paper24", "general"}),
      key("coefficients", Reals{},
          "Coefficients in the law's order, N/mm: a_i, b_j, c_i, d_j for a preset; for general, one per\n"
          "`course` monomial then one per `wale` monomial. [] = all zero.",
          -1e9, 1e9),
      key("course", Strings{"C1", "C2", "W1"},
          "general: monomials of the course force, \"C<p>W<q>\" = εC^p εW^q (e.g. \"C2\", \"C1W1\", \"W1\")."),
      key("wale", Strings{"W1", "W2", "C1"}, "general: monomials of the wale force, same notation."),
      key("shear_stiffness", 0.01, "In-plane shear stiffness G_s, N/mm, > 0 (a knit carries almost no shear).", 0, 1e6),
  };
  const fem::ReferenceFabricParameters rp;
  SectionSpec rf{"reference_fabric",
                 "The reference knit of synthetic experiments (docs/theory/fabric.md §4): J-shaped course and\n"
                 "wale responses (linear, then exponential locking) and a coupling that stiffens under\n"
                 "combined stretch; deliberately outside the polynomial family. Strains: Green–Lagrange.",
                 false,
                 {},
                 {}};
  rf.keys = {
      key("k_C", rp.k_C, "Course initial stiffness, N/mm, > 0.", 0, 1e6),
      key("k_CL", rp.k_CL, "Course locking modulus, N/mm.", 0, 1e6),
      key("eps_CL", rp.eps_CL, "Course locking onset strain, > 0.", 0, 100),
      key("s_CL", rp.s_CL, "Course locking width (strain), > 0.", 0, 100),
      key("k_W", rp.k_W, "Wale initial stiffness, N/mm, > 0.", 0, 1e6),
      key("k_WL", rp.k_WL, "Wale locking modulus, N/mm.", 0, 1e6),
      key("eps_WL", rp.eps_WL, "Wale locking onset strain, > 0.", 0, 100),
      key("s_WL", rp.s_WL, "Wale locking width (strain), > 0.", 0, 100),
      key("k_X", rp.k_X, "Biaxial coupling, N/mm.", 0, 1e6),
      key("k_P", rp.k_P, "Transverse shrinkage coupling, N/mm, >= 0 with k_P² < k_C k_W.", 0, 1e6),
      key("k_J", rp.k_J, "Compression jamming modulus, N/mm, >= 0.", 0, 1e6),
      key("eps_J", rp.eps_J, "Jamming onset (compressive strain magnitude), > 0.", 0, 100),
      key("s_J", rp.s_J, "Jamming width (strain), > 0.", 0, 100),
      key("G_s", rp.G_s, "In-plane shear stiffness, N/mm, > 0.", 0, 1e6),
  };
  law.sections = {mr, nh, co, rs, rf};
  // [[law.region]]: a whole law table per named region (docs/theory.md §5.2).
  SectionSpec region{"region",
                     "The law of one region of the mesh (a Gmsh physical surface): a lesion in healthy skin, a seam\n"
                     "in a knit. The same keys and sub-tables as [law] ([law.region.neo_hookean], …); the regions no\n"
                     "table names keep [law]. Its coefficients are named \"<region>.<coefficient>\" in [[parameter]]\n"
                     "(e.g. \"lesion.mu\"): the ones a project does not name stay fixed.",
                     true,
                     {},
                     {}};
  region.keys = law.keys;
  region.keys.insert(region.keys.begin(), key("name", std::string(""), "The region: a physical surface of the mesh."));
  region.sections = law.sections;
  law.sections.push_back(region);
  return law;
}

io::SectionSpec solver_section() {
  SectionSpec s{
      "solver", "Newton–Raphson with line search and load-step cutback (docs/theory.md §4–§7).", false, {}, {}};
  add_keys(s, fem::SolveOptions{});
  return s;
}

io::SectionSpec test_section() {
  SectionSpec s{"test",
                "One test of the case: its output goes to DIR/<name>/ (steps.csv, step_NNNN.vtu, force.png).",
                true,
                {},
                {}};
  s.keys = {
      key("name", std::string("uniaxial"), "Test name: letters, digits, '_', '-' and '.' (a folder name)."),
      key("kind", std::string("uniaxial"),
          "uniaxial: grip on top, side edge free. biaxial: side edge on a guide (the paper's\n"
          "biaxial-induced test). homogeneous: sliding grip, a uniform field. simple_shear: the law alone\n"
          "at F = [[1, γ], [0, 1]] for γ in the step list (one element; writes gamma, s11, s22, s12).\n"
          "rig: the paper's biaxial-induced rig ([rig]; side, pull, transverse_strain, pull_strain, steps).\n"
          "custom: any mesh of [mesh] (a Gmsh file or geometry, or the generator's) with the conditions of\n"
          "its [[test.boundary]] tables; every boundary they do not name is free; `loads` are step labels.",
          -kInf, kInf, {"uniaxial", "biaxial", "homogeneous", "simple_shear", "rig", "custom"}),
      key("material_angle", 0.0,
          "Degrees from x to the course direction. The grip pulls along y: 0 loads along the wale,\n"
          "90 along the course.",
          -360, 360),
      key("control", std::string("displacement"),
          "What the steps prescribe: the grip displacement (mm, quarter model: the specimen lengthens by\n"
          "twice it) or the full-specimen grip force (N; uniaxial, the grip edge stays straight).",
          -kInf, kInf, {"displacement", "force"}),
      key("grip_holds_x", true,
          "The grip also holds u_x = 0 (a clamp); false = a sliding grip. homogeneous needs false."),
      key("grip_follows_guide", false,
          "Biaxial with a clamp: the clamp's width opens with the guide (u_x = c·x/(width/2) on the grip,\n"
          "a pantograph clamp), so the clamp and a moving guide agree at the corner."),
      key("side", std::string("free"),
          "Side edge x = width/2: free, or guide (u_x prescribed, u_y free). uniaxial needs free and\n"
          "biaxial guide; homogeneous takes either. rig: a number, the full specimen side in mm, > 0\n"
          "(default: [mesh] width; the quarter is side/2 × side/2).",
          -kInf, kInf, {"free", "guide"}),
      key("guide", Reals{},
          "Guide displacement u_x of the side edge, mm (negative narrows the specimen): one value, reached\n"
          "in proportion to the load, or one per step; [] = 0, the width held.",
          -1e5, 1e5),
      key("loads", Reals{},
          "The step list (mm or N as `control` says; γ for simple_shear): strictly increasing from > 0 under\n"
          "force control, any path under displacement control (a lab record's holds and unloading). When\n"
          "empty, `load_max` and `steps` make a uniform list. rig: the pull's grip as measured, one per\n"
          "step (tricot experiment writes them), in place of the uniform list of pull_strain.",
          -1e9, 1e9),
      key("load_max", 10.0, "Last load of the uniform list (mm, N or γ), > 0; used when `loads` is empty.", 0, 1e9),
      key("steps", std::int64_t{10},
          "Steps of the uniform list: load_max · k / steps for k = 1 … steps (rig: the pull's equal\n"
          "increments, 1–1000).",
          1, 100000),
      key("pull", std::string("wale"), "rig: the direction pulled, wale (material_angle 0) or course (90).", -kInf,
          kInf, {"wale", "course"}),
      key("transverse_strain", fem::RigOptions{}.transverse_strain,
          "rig: Green–Lagrange strain set across the pull by the guides, then held, >= -0.4.", -kInf, kInf),
      key("pull_strain", fem::RigOptions{}.pull_strain,
          "rig: nominal Green–Lagrange strain along the pull at the last step, > 0.", -kInf, kInf),
  };
  s.keys.push_back(key("fit_steps", Reals{},
                       "tricot identify: the steps to fit, chosen among the experiment's (1-based numbers of its\n"
                       "forces.csv rows, increasing), e.g. [5, 10, 15, 20]: the FE solves these steps alone and the\n"
                       "other frames' data are left out (cumulative field data only). Empty = every step.",
                       1, 1e9));
  s.keys.push_back(key("force_scale", 1.0,
                       "custom: the test's force is this times the resultant of the boundary whose `force` is set\n"
                       "(2 for a half model whose line of symmetry carries the other half), > 0.",
                       0, 1e6));
  for (auto& k : s.keys)
    if (k.name == "side") k.or_number = true;
  SectionSpec b{
      "boundary",
      "custom: the conditions of one named boundary (docs/theory.md §6). A component may be held (`fix`), set\n"
      "by a line of symmetry, or prescribed per step (`ux`, `uy`, or columns of a CSV `series`); a\n"
      "rigid grip prescribes both. `force` makes its resultant the test's measured force.",
      true,
      {},
      {}};
  b.keys = {
      key("name", std::string(""), "The boundary: a Gmsh physical curve or point, or left/bottom/top/right."),
      key("fix", Strings{}, "Components held at 0: [\"x\"], [\"y\"] or [\"x\", \"y\"]."),
      key("symmetry", false, "A line of symmetry (x = const or y = const): its normal component held at 0."),
      key("ux", Reals{}, "u_x per step, mm (one value per step; any sign, holds and unloading allowed).", -1e6, 1e6),
      key("uy", Reals{}, "u_y per step, mm (one value per step).", -1e6, 1e6),
      key("series", std::string(""), "A CSV (relative to this file's folder) whose columns give ux and uy per step."),
      key("ux_column", std::string(""), "series: the column of u_x, mm."),
      key("uy_column", std::string(""), "series: the column of u_y, mm."),
      key("force", std::string(""), "x or y: this boundary's resultant along it is the test's force (N).", -kInf, kInf,
          {"", "x", "y"}),
      key("proportional", false,
          "ux and uy are displacements per mm of the node's x and y (u_x = ux·X, mm/mm): a clamp that spreads\n"
          "about the axis, as the paper's pantograph clips follow the guides."),
      key("tie", 0.0,
          "> 0: the components this table holds or prescribes are held by compliant ties instead (N/mm per mm\n"
          "of boundary, lumped on the nodes by their share of its length): a compliant clamp or a guide that\n"
          "the fabric slides along. 0 = rigid.",
          0, 1e12),
      key("tie_end", Reals{},
          "[x, y], mm: the tie ends at the boundary's point closest to this one; it runs from the boundary's\n"
          "far end up to it (the nodes beyond are left free): a guide that ends short of the clips.",
          -1e9, 1e9),
      key("tie_taper", 0.0, "mm: the tie's stiffness falls linearly to 0 over this length before tie_end.", 0, 1e9),
      key("tie_lumping", std::string("consistent"),
          "How the tie is shared among the nodes: \"consistent\" (∫ N_i ds over each element side: a uniform tie\n"
          "pulls a quadratic side as a uniform traction does) or \"segments\" (half of each node-to-node\n"
          "segment, the built-in rig's rule; the same on linear elements).",
          -kInf, kInf, {"consistent", "segments"}),
  };
  s.sections = {test_mesh_section(), b};
  return s;
}

io::SectionSpec rig_section() {
  SectionSpec s{
      "rig",
      "The paper's biaxial-induced rig (docs/theory.md §6, paper §3.1.2), shared by every [[test]] of kind =\n"
      "\"rig\": clips at the grip, lateral guides tied to the fabric that hold the transverse dimension\n"
      "and end short of the clips. The transverse dimension is set first, then held during the pull.",
      false,
      {},
      {}};
  add_keys(s, fem::RigOptions{});
  return s;
}

io::SectionSpec case_schema() {
  SectionSpec root{"",
                   "tricot simulate: a case file. Finite-element models of tests on a knitted-fabric specimen\n"
                   "(plane-stress membrane, quarter specimen, docs/theory.md §4–§6). Units: mm, N, N/mm, degrees.",
                   false,
                   {},
                   {}};
  root.sections = {mesh_section(), law_section(), solver_section(), rig_section(), test_section()};
  return root;
}

// ---------------------------------------------------------------------------------------------------
// Specs from validated tables

MeshSpec MeshSpec::from_config(const io::Node& n) {
  MeshSpec m;
  read_keys(n, m);
  read_keys(n, static_cast<fem::MeshOptions&>(m));
  m.folder = n.file().empty() ? std::string() : fs::path(n.file()).parent_path().string();
  m.origin = Origin(n);
  return m;
}

BoundarySpec BoundarySpec::from_config(const io::Node& n) {
  BoundarySpec b;
  b.name = n.string("name"), b.fix = n.strings("fix"), b.symmetry = n.boolean("symmetry");
  b.ux = n.reals("ux"), b.uy = n.reals("uy");
  b.series = n.string("series"), b.ux_column = n.string("ux_column"), b.uy_column = n.string("uy_column");
  b.force = n.string("force");
  b.proportional = n.boolean("proportional");
  b.tie = n.real("tie"), b.tie_end = n.reals("tie_end"), b.tie_taper = n.real("tie_taper");
  b.tie_lumping = n.string("tie_lumping");
  b.folder = n.file().empty() ? std::string() : fs::path(n.file()).parent_path().string();
  b.origin = Origin(n);
  return b;
}

TestMeshSpec TestMeshSpec::from_config(const io::Node& n) {
  TestMeshSpec m;
  read_keys(n, m);
  m.origin = Origin(n);
  return m;
}

MooneyRivlinSpec::MooneyRivlinSpec() {
  // Default: the paper's validation set (docs/validation.md §1), a rubber-like S curve.
  for (const auto& t : fem::paper_mooney_rivlin_terms()) {
    terms.push_back(fmt::format("C{}{}", t.i, t.j));
    values.push_back(t.C);
  }
}

namespace {

// One law table: [law] or a [[law.region]].
LawSpec law_table(const io::Node& law) {
  LawSpec l;
  l.type = law.string("type");
  l.wrinkling = law.boolean("wrinkling");
  read_keys(law, l.wrinkling_options);
  l.origin = Origin(law);
  const Node& mr = law.section("mooney_rivlin");
  l.mooney_rivlin.terms = mr.strings("terms"), l.mooney_rivlin.values = mr.reals("values");
  l.mooney_rivlin.kappa = mr.real("kappa"), l.mooney_rivlin.kinematics = mr.string("kinematics");
  l.mooney_rivlin.origin = Origin(mr);
  const Node& nh = law.section("neo_hookean");
  l.neo_hookean.mu = nh.real("mu"), l.neo_hookean.lambda = nh.real("lambda");
  l.neo_hookean.kinematics = nh.string("kinematics");
  if (nh.given("E") || nh.given("nu")) {
    if (!nh.given("E") || !nh.given("nu"))
      nh.fail(nh.given("E") ? "nu" : "E", "E and nu go together", "one of them", "both, or mu and lambda");
    if (nh.given("mu") || nh.given("lambda"))
      nh.fail(nh.given("mu") ? "mu" : "lambda", "give E and nu, or mu and lambda, not both", "both", "one pair");
    l.neo_hookean.E = nh.real("E"), l.neo_hookean.nu = nh.real("nu");
  }
  l.neo_hookean.origin = Origin(nh);
  const Node& co = law.section("corotational");
  CorotationalSpec& c = l.corotational;
  c.moduli = co.string("moduli");
  c.G = co.real("G"), c.K = co.real("K");
  c.D11 = co.real("D11"), c.D22 = co.real("D22"), c.D12 = co.real("D12"), c.D66 = co.real("D66");
  c.origin = Origin(co);
  const Node& rs = law.section("response_surface");
  ResponseSurfaceSpec& r = l.response_surface;
  r.preset = rs.string("preset");
  r.coefficients = rs.reals("coefficients");
  r.course = rs.strings("course"), r.wale = rs.strings("wale");
  r.shear_stiffness = rs.real("shear_stiffness");
  r.origin = Origin(rs);
  const Node& rf = law.section("reference_fabric");
  ReferenceFabricSpec& p = l.reference_fabric;
  p.k_C = rf.real("k_C"), p.k_CL = rf.real("k_CL"), p.eps_CL = rf.real("eps_CL"), p.s_CL = rf.real("s_CL");
  p.k_W = rf.real("k_W"), p.k_WL = rf.real("k_WL"), p.eps_WL = rf.real("eps_WL"), p.s_WL = rf.real("s_WL");
  p.k_X = rf.real("k_X"), p.k_P = rf.real("k_P"), p.k_J = rf.real("k_J"), p.eps_J = rf.real("eps_J");
  p.s_J = rf.real("s_J"), p.G_s = rf.real("G_s");
  p.origin = Origin(rf);
  return l;
}

}  // namespace

LawSpec LawSpec::from_config(const io::Node& law) {
  LawSpec l = law_table(law);
  for (const io::Node& r : law.array("region")) {
    if (!r.given("type"))  // the default law would take the region silently
      r.fail("type", "a region's law needs its type", "none", "mooney_rivlin, neo_hookean, corotational, …");
    l.region.push_back(law_table(r));
    l.region.back().name = r.string("name");
  }
  return l;
}

SolverSpec SolverSpec::from_config(const io::Node& s) {
  SolverSpec o;
  read_keys(s, static_cast<fem::SolveOptions&>(o));
  o.origin = Origin(s);
  return o;
}

RigSpec RigSpec::from_config(const io::Node& n) {
  RigSpec r;
  read_keys(n, static_cast<fem::RigOptions&>(r));
  r.origin = Origin(n);
  return r;
}

TestSpec TestSpec::from_config(const io::Node& n) {
  TestSpec t;
  t.name = n.string("name");
  t.kind = n.string("kind");
  t.material_angle = n.real("material_angle");
  t.control = n.string("control");
  if (n.given("grip_holds_x")) t.grip_holds_x = n.boolean("grip_holds_x");
  t.grip_follows_guide = n.boolean("grip_follows_guide");
  if (n.given("side")) {
    const io::Value& v = n.value("side");
    if (const auto* w = std::get_if<std::string>(&v)) t.side = *w;
    else t.side = std::get<double>(v);
  }
  t.guide = n.reals("guide");
  t.loads = n.reals("loads");
  t.fit_steps = n.reals("fit_steps");
  t.load_max = n.real("load_max");
  t.uniform_loads_given = n.given("load_max") || n.given("steps");
  t.steps = static_cast<int>(n.integer("steps"));
  t.pull = n.string("pull");
  t.transverse_strain = n.real("transverse_strain");
  t.pull_strain = n.real("pull_strain");
  t.mesh = TestMeshSpec::from_config(n.section("mesh"));
  for (const auto& b : n.array("boundary")) t.boundary.push_back(BoundarySpec::from_config(b));
  t.force_scale = n.real("force_scale");
  t.origin = Origin(n);
  return t;
}

CaseSpec CaseSpec::from_config(const io::Node& root) {
  CaseSpec c;
  c.mesh = MeshSpec::from_config(root.section("mesh"));
  c.law = LawSpec::from_config(root.section("law"));
  c.solver = SolverSpec::from_config(root.section("solver"));
  c.rig = RigSpec::from_config(root.section("rig"));
  for (const auto& t : root.array("test")) c.test.push_back(TestSpec::from_config(t));
  c.origin = Origin(root);
  return c;
}

// ---------------------------------------------------------------------------------------------------
// Checks and engine values

namespace {

// Whether [test.mesh] `over` gives the key `name` (a non-zero, non-empty value).
bool gives(const TestMeshSpec& over, std::string_view name) {
  bool given = false;
  for_each_option<TestMeshSpec>([&](const auto& k) {
    if (k.name() == name) given = over.*k.member != std::remove_cvref_t<decltype(over.*k.member)>{};
  });
  return given;
}

// The mesh of [mesh] with the keys of `over` in place (non-zero, non-empty); each check placed at
// the table that gave the value.
fem::MeshOptions mesh_options(const MeshSpec& mesh, const TestMeshSpec* over) {
  // The full sizes, checked with the value the file gave (fem checks the quarter's, half of it).
  auto half = [&](double MeshSpec::*m, double TestMeshSpec::*t, const char* key) {
    const bool given = over && over->*t != 0;
    const double full = given ? over->*t : mesh.*m;
    if (!(full > 0)) (given ? over->origin : mesh.origin).fail(key, "must be positive", num(full), "> 0");
    return full / 2;
  };
  fem::MeshOptions o = mesh;  // [mesh]'s generator options; the quarter's sizes below
  o.width = half(&MeshSpec::width, &TestMeshSpec::width, "width");
  o.height = half(&MeshSpec::height, &TestMeshSpec::height, "height");
  if (over) {
    if (!over->element.empty()) {
      const auto type = fem::element_type(over->element);
      if (!type)
        over->origin.fail("element", "not an element type", "\"" + over->element + "\"", "Q4, Q8, T3, T6 or \"\"");
      o.type = *type;
    }
    if (over->nx != 0) o.nx = over->nx;
    if (over->ny != 0) o.ny = over->ny;
    if (over->grading != 0) o.grading = over->grading;
    if (over->grading_x != 0) o.grading_x = over->grading_x;
  }
  try {
    o.validate();
  } catch (const InputError& e) {
    const std::string& key = e.where().key;
    const bool given = over && gives(*over, std::string_view(key).substr(key.find('.') + 1));
    rethrow_fem(e, {.mesh = given ? &over->origin : &mesh.origin});
  }
  return o;
}

// A unit square of one element: nodes at the corners (and mid-sides for Q8), edges as a quarter mesh.
fem::Mesh unit_element(fem::ElementType type) {
  fem::MeshOptions o;
  o.width = o.height = 1;
  o.nx = o.ny = 1;
  o.type = type;
  return fem::make_quarter_mesh(o);
}

// Issue 14: a mesh too big for this machine is refused before any work, with the number, rather than
// ending in std::bad_alloc after minutes. Peak memory of `tricot simulate` measured 2.6 KB (Q4, 80 k
// dofs) to 3.0 KB (Q8, 240 k dofs) per dof, growing slowly with the factor's fill-in (docs/validation.md,
// issue 14): 4 KB per dof is the estimate.
constexpr double kBytesPerDof = 4096;

double mesh_dofs(const fem::MeshOptions& o) {
  const double nx = o.nx, ny = o.ny;
  const double nodes = o.type == fem::ElementType::Q4 || o.type == fem::ElementType::T3 ? (nx + 1) * (ny + 1)
                       : o.type == fem::ElementType::T6                                 ? (2 * nx + 1) * (2 * ny + 1)
                                                        : (2 * nx + 1) * (2 * ny + 1) - nx * ny;
  return 2 * nodes;
}

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? double(pages) * double(page) : 0.0;
}

void check_mesh_fits(const fem::MeshOptions& o, const Origin& where) {
  const double need = kBytesPerDof * mesh_dofs(o), have = physical_memory_bytes();
  if (have > 0 && need > have)
    where.fail(o.nx >= o.ny ? "nx" : "ny", "the mesh does not fit in this machine's memory",
               fmt::format("{} × {} {} elements: {:.0f} dofs, about {:.1f} GB", o.nx, o.ny, fem::to_string(o.type),
                           mesh_dofs(o), need / 1e9),
               fmt::format("at most {:.1f} GB of memory ({:.0f} dofs)", have / 1e9, have / kBytesPerDof));
}

std::string side_text(const std::variant<std::string, double>& side) {
  if (const auto* w = std::get_if<std::string>(&side)) return "\"" + *w + "\"";
  return num(std::get<double>(side));
}

}  // namespace

fem::MeshOptions TestMeshSpec::options(const MeshSpec& mesh) const { return mesh_options(mesh, this); }

TestKind TestSpec::test_kind() const {
  if (kind == "biaxial") return TestKind::biaxial;
  if (kind == "homogeneous") return TestKind::homogeneous;
  if (kind == "simple_shear") return TestKind::simple_shear;
  if (kind == "rig") return TestKind::rig;
  if (kind == "custom") return TestKind::custom;
  if (kind != "uniaxial")
    origin.fail("kind", "unknown test kind", "\"" + kind + "\"",
                "uniaxial, biaxial, homogeneous, simple_shear, rig or custom");
  return TestKind::uniaxial;
}

fem::MeshOptions TestSpec::mesh_options(const MeshSpec& case_mesh) const {
  fem::MeshOptions o = mesh.options(case_mesh);
  if (test_kind() == TestKind::rig) {
    const auto* mm = side ? std::get_if<double>(&*side) : nullptr;
    o.width = o.height = 0.5 * (mm ? *mm : case_mesh.width);
  }
  return o;
}

fem::TestModel TestSpec::model(const MeshSpec& case_mesh, const RigSpec& rig) const {
  const TestKind k = test_kind();
  if (k == TestKind::custom) return custom_model(case_mesh);
  if (case_mesh.from_gmsh())
    case_mesh.origin.fail(case_mesh.file.empty() ? "geometry" : "file", "a Gmsh mesh is for tests of kind = \"custom\"",
                          "test '" + name + "' of kind \"" + kind + "\"",
                          "kind = \"custom\" with [[test.boundary]] tables");
  if (!boundary.empty())
    origin.fail("boundary", "[[test.boundary]] tables are for tests of kind = \"custom\"", "\"" + kind + "\"",
                "custom");
  const fem::MeshOptions mo = mesh.options(case_mesh);
  if (k != TestKind::simple_shear) check_mesh_fits(mo, mesh.nx != 0 || mesh.ny != 0 ? mesh.origin : case_mesh.origin);
  if (k == TestKind::rig) {
    // The rig sets its own loads, grip and guide: keys of the other kinds would be ignored, so refuse them.
    if (side && std::holds_alternative<std::string>(*side))
      origin.fail("side", "a rig test's side is the specimen side in mm", side_text(*side), "a number > 0");
    // `loads`: the pull's grip as measured (tricot experiment's forces.csv), one per step, in place
    // of the uniform list of pull_strain and steps.
    if (!loads.empty() && loads.size() != static_cast<std::size_t>(steps))
      origin.fail("loads", "a rig test's measured loads are one per step", fmt::format("{} loads", loads.size()),
                  fmt::format("{} (steps)", steps));
    if (!guide.empty())
      origin.fail("guide", "a rig test's guide comes from transverse_strain", io::to_toml(guide), "none");
    if (control != "displacement")
      origin.fail("control", "a rig test pulls under displacement control", "\"" + control + "\"", "displacement");
    fem::RigOptions o = rig;  // [rig]'s; the test's own below
    o.name = name;
    o.side = side ? std::get<double>(*side) : case_mesh.width;
    o.pull = pull == "course" ? fem::PullDirection::course : fem::PullDirection::wale;
    o.transverse_strain = transverse_strain;
    o.pull_strain = pull_strain;
    o.steps = steps;
    o.nx = mo.nx, o.ny = mo.ny, o.element = mo.type;
    o.grading_y = mo.grading, o.grading_x = mo.grading_x;
    try {
      fem::TestModel m = fem::make_rig_test(o);  // RigOptions::validate and TestModel::validate: the one check
      if (!loads.empty()) {
        m.loads = loads;
        m.validate();
      }
      return m;
    } catch (const InputError& e) {
      rethrow_fem(e, {.mesh = &case_mesh.origin, .test = &origin, .rig = &rig.origin});
    }
  }
  if (side && std::holds_alternative<double>(*side))
    origin.fail("side", "a number is the specimen side of a rig test", side_text(*side),
                "free or guide, or kind = \"rig\"");
  const std::string side_word = side ? std::get<std::string>(*side) : std::string("free");

  fem::TestModel t;
  t.name = name;
  // The step list: `loads`, or load_max · k / steps.
  if (!loads.empty()) {
    t.loads = loads;
  } else {
    if (!(load_max > 0)) origin.fail("load_max", "must be positive (or give `loads`)", num(load_max), "> 0");
    t.loads.resize(static_cast<std::size_t>(steps));
    for (int s = 1; s <= steps; ++s) t.loads[static_cast<std::size_t>(s - 1)] = load_max * double(s) / double(steps);
  }
  t.material_angle = material_angle;

  if (k == TestKind::simple_shear) {
    // One element with every node prescribed: the law's homogeneous response (docs/theory.md §4 validation).
    t.mesh = unit_element(mo.type);
    t.grip_holds_x = false;
    t.side = fem::SideEdge::free;
    if (control != "displacement")
      origin.fail("control", "simple_shear prescribes the shear γ", "\"" + control + "\"", "displacement");
    return t;
  }

  t.control = control == "force" ? fem::GripControl::force : fem::GripControl::displacement;
  t.grip_holds_x = grip_holds_x.value_or(true);
  t.grip_follows_guide = grip_follows_guide;
  switch (k) {
    case TestKind::uniaxial:
      if (side_word != "free")
        origin.fail("side", "a uniaxial test has a free side edge; use kind = \"biaxial\" for a guide",
                    "\"" + side_word + "\"", "free");
      t.side = fem::SideEdge::free;
      break;
    case TestKind::biaxial:
      if (side && side_word != "guide")
        origin.fail("side", "a biaxial test has its side edge on a guide", "\"" + side_word + "\"", "guide");
      t.side = fem::SideEdge::guide;
      break;
    case TestKind::homogeneous:
      if (grip_holds_x && *grip_holds_x)
        origin.fail("grip_holds_x", "a homogeneous test needs a sliding grip", "true", "false");
      t.grip_holds_x = false;
      t.side = side_word == "guide" ? fem::SideEdge::guide : fem::SideEdge::free;
      break;
    case TestKind::simple_shear:
    case TestKind::rig:
    case TestKind::custom: break;
  }
  if (t.side == fem::SideEdge::guide) {
    t.guide = guide;
    if (t.guide.empty()) t.guide = {0.0};
    for (std::size_t g = 0; g < t.guide.size(); ++g)
      if (t.guide[g] <= -mo.width)
        origin.fail("guide", fmt::format("guide value {} would pull the side edge past the symmetry axis", g + 1),
                    num(t.guide[g]), fmt::format("> -{} mm, half the width", num(mo.width)));
  } else if (!guide.empty()) {
    origin.fail("guide", "guide values given but the side edge is free", io::to_toml(guide),
                "none, or side = \"guide\"");
  }
  if (t.control == fem::GripControl::force && t.side == fem::SideEdge::guide)
    origin.fail("control", "force control is for a free side edge (uniaxial)", "\"force\"", "displacement");
  if (t.control == fem::GripControl::force || loads.empty()) {  // displacement control: any path (issue 29)
    if (!(t.loads.front() > 0))
      origin.fail(loads.empty() ? "load_max" : "loads", "the first load must be positive", num(t.loads.front()), "> 0");
    for (std::size_t k = 1; k < t.loads.size(); ++k)
      if (!(t.loads[k] > t.loads[k - 1]))
        origin.fail("loads",
                    fmt::format("under force control the loads must increase strictly (step {} goes backwards)", k + 1),
                    num(t.loads[k]), "> " + num(t.loads[k - 1]));
  }
  t.mesh = fem::make_quarter_mesh(mo);
  try {
    t.validate();
  } catch (const InputError& e) {
    rethrow_fem(e, {.test = &origin});
  }
  return t;
}

namespace {

// A path of a config file's key: as given when absolute, else relative to the file's folder.
std::string resolve(const std::string& folder, const std::string& path) {
  return fs::path(path).is_absolute() || folder.empty() ? path : (fs::path(folder) / path).string();
}

// An error of the Gmsh reader, which names the mesh file and the key, placed at the config key too.
[[noreturn]] void rethrow_mesh(const InputError& e, const Origin& origin, const char* key) {
  const Location at = origin.where(key);
  const std::string problem = e.where().file + ": " + problem_of(e);
  if (dynamic_cast<const FileError*>(&e)) throw FileError(at, problem);
  throw InputError(at, problem);
}

}  // namespace

std::vector<std::string> MeshSpec::region_names() const {
  return from_gmsh() ? gmsh_mesh().region_names : std::vector<std::string>{};
}

fem::Mesh MeshSpec::gmsh_mesh() const {
  if (!file.empty() && !geometry.empty())
    origin.fail("geometry", "a mesh comes from a file or a geometry, not both", "\"" + geometry + "\"", "\"\"");
  const char* key = file.empty() ? "geometry" : "file";
  try {
    if (!file.empty()) return fem::read_gmsh(resolve(folder, file));
    fem::GeometryMeshOptions o;
    o.size = size;
    o.order = type == fem::ElementType::T6 || type == fem::ElementType::Q8 ? 2 : 1;
    o.quads = !fem::is_triangle(type);
    return fem::mesh_geometry(resolve(folder, geometry), o);
  } catch (const InputError& e) {
    rethrow_mesh(e, origin, key);
  }
}

fem::TestModel TestSpec::custom_model(const MeshSpec& case_mesh) const {
  fem::TestModel t;
  t.name = name;
  t.material_angle = material_angle;
  if (case_mesh.from_gmsh()) {
    t.mesh = case_mesh.gmsh_mesh();
  } else if (case_mesh.whole) {  // the full rectangle, centred: the quarter generator at twice the size, moved
    fem::MeshOptions o = mesh.options(case_mesh);
    o.width *= 2, o.height *= 2;
    t.mesh = fem::make_quarter_mesh(o);
    t.mesh.X.row(0).array() -= o.width / 2;
    t.mesh.X.row(1).array() -= o.height / 2;
  } else {
    t.mesh = fem::make_quarter_mesh(mesh.options(case_mesh));
  }
  if (loads.empty()) {  // step labels 1 … steps
    t.loads.resize(static_cast<std::size_t>(steps));
    for (int k = 0; k < steps; ++k) t.loads[static_cast<std::size_t>(k)] = k + 1;
  } else {
    t.loads = loads;
  }
  if (boundary.empty())
    origin.fail("boundary", "a custom test needs [[test.boundary]] tables", "none",
                "at least one condition (fixed, symmetry, or a displacement per step)");
  t.force_scale = force_scale;
  for (const BoundarySpec& b : boundary) {
    const Origin& o = b.origin;
    std::vector<int> nodes;
    try {
      nodes = t.mesh.boundary(b.name, "name");
    } catch (const InputError& e) {
      o.fail("name", problem_of(e));
    }
    auto component = [&](const std::string& word, const char* key) {
      if (word != "x" && word != "y") o.fail(key, "not a component", "\"" + word + "\"", "\"x\" or \"y\"");
      return word == "x" ? 0 : 1;
    };
    const size_t first = t.conditions.size();
    for (const std::string& c : b.fix) t.conditions.push_back({b.name, component(c, "fix"), {}});
    if (b.symmetry) {
      // The boundary lies on x = const (normal x) or y = const (normal y).
      const Eigen::Matrix2Xd X = t.mesh.X(Eigen::all, nodes);
      const Eigen::Vector2d spread = X.rowwise().maxCoeff() - X.rowwise().minCoeff();
      const double size = (t.mesh.X.rowwise().maxCoeff() - t.mesh.X.rowwise().minCoeff()).maxCoeff();
      if (spread.minCoeff() > 1e-9 * size)
        o.fail("symmetry", "the boundary '" + b.name + "' is not a straight line x = const or y = const",
               fmt::format("spread {} × {} mm", num(spread(0)), num(spread(1))), "a line parallel to x or y");
      t.conditions.push_back({b.name, spread(0) <= spread(1) ? 0 : 1, {}});
    }
    Reals ux = b.ux, uy = b.uy;
    if (!b.series.empty()) {
      if (b.ux_column.empty() && b.uy_column.empty())
        o.fail("series", "a series needs ux_column or uy_column", "\"" + b.series + "\"", "a column name");
      const std::string path = resolve(b.folder, b.series);
      const io::Table table = io::read_csv(path);
      if (!b.ux_column.empty()) ux = table.values(b.ux_column, path);
      if (!b.uy_column.empty()) uy = table.values(b.uy_column, path);
    }
    const std::pair<const Reals*, const char*> series[] = {{&ux, "ux"}, {&uy, "uy"}};
    for (int c = 0; c < 2; ++c) {
      const Reals& v = *series[c].first;
      if (v.empty()) continue;
      if (v.size() != t.loads.size())
        o.fail(b.series.empty() ? series[c].second : (c == 0 ? "ux_column" : "uy_column"),
               fmt::format("the series of boundary '{}' has {} values for {} steps", b.name, v.size(), t.loads.size()),
               fmt::format("{} values", v.size()), fmt::format("one per step ({})", t.loads.size()));
      t.conditions.push_back({b.name, c, v});
      t.conditions.back().proportional = b.proportional;
    }
    if (b.proportional && ux.empty() && uy.empty())
      o.fail("proportional", "proportional values need ux or uy", "true", "ux or uy (mm per mm)");
    if (b.tie > 0) {
      if (b.symmetry) o.fail("tie", "a line of symmetry is exact: it takes no tie", num(b.tie), "0, or no symmetry");
      if (t.conditions.size() == first)
        o.fail("tie", "a tie needs the components it holds: fix, ux or uy", num(b.tie), "fix = [\"x\"], ux or uy");
      if (!b.tie_end.empty() && b.tie_end.size() != 2)
        o.fail("tie_end", "not a point", fmt::format("{} values", b.tie_end.size()), "[x, y] in mm");
      for (size_t i = first; i < t.conditions.size(); ++i) {
        fem::BoundaryCondition& c = t.conditions[i];
        c.tie = b.tie, c.tie_taper = b.tie_taper, c.tie_consistent = b.tie_lumping == "consistent";
        if (!b.tie_end.empty()) c.tie_end = Vec2(b.tie_end[0], b.tie_end[1]);
        try {
          t.tie_stiffness(i);
        } catch (const InputError& e) {
          o.fail(e.where().key.substr(e.where().key.rfind('.') + 1), problem_of(e));
        }
      }
    } else if (!b.tie_end.empty() || b.tie_taper != 0) {
      o.fail(b.tie_end.empty() ? "tie_taper" : "tie_end", "a tie's end and taper need a tie", "tie = 0", "tie > 0");
    }
    if (b.tie_taper > 0 && b.tie_end.empty())
      o.fail("tie_taper", "a taper needs the tie's end", num(b.tie_taper), "tie_end = [x, y]");
    if (!b.force.empty()) {
      if (!t.force_boundary.empty())
        o.fail("force", "two boundaries give the test's force", "\"" + t.force_boundary + "\" and \"" + b.name + "\"",
               "one");
      t.force_boundary = b.name;
      t.force_component = b.force == "x" ? 0 : 1;
    }
  }
  try {
    t.validate();
  } catch (const InputError& e) {
    rethrow_fem(e, {.mesh = &case_mesh.origin, .test = &origin});
  }
  return t;
}

std::unique_ptr<fem::Law> LawSpec::law(const std::vector<std::string>& mesh_regions) const {
  if (region.empty()) return region_law();
  if (mesh_regions.empty())
    region.front().origin.fail("name", "region laws need a mesh with named regions (Gmsh physical surfaces)",
                               "\"" + region.front().name + "\"", "[mesh] file or geometry with physical surfaces");
  std::vector<std::unique_ptr<fem::Law>> laws;
  std::vector<std::string> prefixes{""};
  laws.push_back(region_law());
  std::vector<int> law_of_region(mesh_regions.size(), 0);
  for (const LawSpec& r : region) {
    const auto at = std::find(mesh_regions.begin(), mesh_regions.end(), r.name);
    if (at == mesh_regions.end()) {
      const std::string hint = fem::closest_name(r.name, mesh_regions);
      r.origin.fail(
          "name",
          "no region of the mesh is named '" + r.name + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)"),
          "\"" + r.name + "\"", "a physical surface of the mesh");
    }
    if (std::find(prefixes.begin(), prefixes.end(), r.name) != prefixes.end())
      r.origin.fail("name", "a second law for the region '" + r.name + "'", "\"" + r.name + "\"",
                    "one table per region");
    law_of_region[static_cast<size_t>(at - mesh_regions.begin())] = static_cast<int>(laws.size());
    laws.push_back(r.region_law());
    prefixes.push_back(r.name);
  }
  return std::make_unique<fem::RegionLaws>(std::move(laws), std::move(prefixes), std::move(law_of_region));
}

std::unique_ptr<fem::Law> LawSpec::region_law() const {
  std::unique_ptr<fem::Law> inner = inner_law();
  if (!wrinkling) return inner;
  try {
    return std::make_unique<fem::WrinklingLaw>(*inner, wrinkling_options);  // its options' one check
  } catch (const InputError& e) {
    rethrow(e);
  }
}

void LawSpec::rethrow(const InputError& e) const {
  const std::string& k = e.where().key;
  if (!e.where().file.empty() || k.rfind("law.", 0) != 0) throw;
  const std::string key = k.substr(4);
  const auto dot = key.find('.');
  const std::string table = key.substr(0, dot);
  const Origin* sub = table == "mooney_rivlin"      ? &mooney_rivlin.origin
                      : table == "neo_hookean"      ? &neo_hookean.origin
                      : table == "corotational"     ? &corotational.origin
                      : table == "response_surface" ? &response_surface.origin
                      : table == "reference_fabric" ? &reference_fabric.origin
                                                    : nullptr;
  if (sub && dot != std::string::npos) throw InputError(sub->where(key.substr(dot + 1)), problem_of(e));
  throw InputError(origin.where(key), problem_of(e));
}

std::unique_ptr<fem::Law> LawSpec::inner_law() const {
  // The law's constructor is the one check of its coefficients on their way to the engine. It names a
  // bad one by its key relative to the law's table (`law.mooney_rivlin.values`, `law.neo_hookean.mu`, …),
  // so the error is placed at that key of the sub-table's Origin as it is (rethrow).
  auto build = [this](auto&& make) -> std::unique_ptr<fem::Law> {
    try {
      return make();
    } catch (const InputError& e) {
      rethrow(e);
    }
  };
  if (type == "mooney_rivlin") {
    const MooneyRivlinSpec& s = mooney_rivlin;
    if (s.terms.size() != s.values.size())
      s.origin.fail("values", "one value per term", fmt::format("{} values", s.values.size()),
                    fmt::format("{} as in terms", s.terms.size()));
    std::vector<fem::MooneyRivlinTerm> terms;
    for (std::size_t k = 0; k < s.terms.size(); ++k) {
      const std::string& n = s.terms[k];
      if (n.size() != 3 || n[0] != 'C' || !std::isdigit(static_cast<unsigned char>(n[1])) ||
          !std::isdigit(static_cast<unsigned char>(n[2])) || n == "C00")
        s.origin.fail("terms", fmt::format("term {} is not a name C<i><j>", k + 1), "\"" + n + "\"",
                      "C10, C01, C20, C21, C03, …");
      terms.push_back({n[1] - '0', n[2] - '0', s.values[k]});
    }
    const auto kinematics =
        s.kinematics == "plane_strain" ? fem::Kinematics::plane_strain : fem::Kinematics::plane_stress;
    if (s.kappa > 0)
      return build(
          [&] { return std::make_unique<fem::CompressibleMooneyRivlin>(std::move(terms), s.kappa, kinematics); });
    if (kinematics == fem::Kinematics::plane_strain)
      s.origin.fail("kinematics", "an incompressible sheet cannot be held across (C33 = 1 with det C = 1 locks it)",
                    "\"plane_strain\"", "kappa > 0, or plane_stress");
    return build([&] { return std::make_unique<fem::MooneyRivlin>(std::move(terms)); });
  }
  if (type == "neo_hookean") {
    const NeoHookeanSpec& s = neo_hookean;
    const auto kinematics =
        s.kinematics == "plane_strain" ? fem::Kinematics::plane_strain : fem::Kinematics::plane_stress;
    if (s.E)
      return build([&] { return std::make_unique<fem::NeoHookean>(fem::YoungPoisson{*s.E, *s.nu}, kinematics); });
    return build([&] { return std::make_unique<fem::NeoHookean>(s.mu, s.lambda, kinematics); });
  }
  if (type == "corotational") {
    const CorotationalSpec& s = corotational;
    return build([&] {
      return s.moduli == "isotropic"
                 ? std::make_unique<fem::CorotationalOrthotropic>(fem::CorotationalOrthotropic::isotropic(s.G, s.K))
                 : std::make_unique<fem::CorotationalOrthotropic>(s.D11, s.D22, s.D12, s.D66);
    });
  }
  if (type == "response_surface") {
    const ResponseSurfaceSpec& s = response_surface;
    return build([&] {
      fem::ResponseSurface rs = s.preset == "general"
                                    ? fem::ResponseSurface(monomials(s.origin, s.course, "course"),
                                                           monomials(s.origin, s.wale, "wale"), s.shear_stiffness)
                                    : fem::ResponseSurface::preset(s.preset, s.shear_stiffness);
      const Reals& c = s.coefficients;
      if (!c.empty()) {
        if (c.size() != static_cast<std::size_t>(rs.coefficients().size()))
          s.origin.fail("coefficients", "one coefficient per term of the law", fmt::format("{} values", c.size()),
                        fmt::format("{} ({})", rs.coefficients().size(), join(rs.coefficient_names())));
        rs.set_coefficients(Eigen::Map<const Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size())));
      }
      return std::make_unique<fem::ResponseSurface>(std::move(rs));
    });
  }
  if (type == "reference_fabric") {
    return build([&] {
      return std::make_unique<fem::ReferenceFabric>(
          static_cast<const fem::ReferenceFabricParameters&>(reference_fabric));
    });
  }
  origin.fail("type", "unknown law", "\"" + type + "\"",
              "mooney_rivlin, neo_hookean, corotational, response_surface or reference_fabric");
}

fem::SolveOptions SolverSpec::options() const {
  try {
    validate();
  } catch (const InputError& e) {
    rethrow_fem(e, {.solver = &origin});
  }
  return *this;
}

void CaseSpec::check_tests() const {
  if (test.empty()) origin.fail("test", "the case has no [[test]]", "none", "at least one [[test]] table");
  std::set<std::string> seen;
  for (const auto& t : test) {
    const std::string& name = t.name;
    const bool ok = !name.empty() && name != "." && name != ".." &&
                    name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") ==
                        std::string::npos;
    if (!ok) t.origin.fail("name", "not usable as a folder name", "\"" + name + "\"", "letters, digits, '_', '-', '.'");
    if (!seen.insert(name).second)
      t.origin.fail("name", "two tests have this name", "\"" + name + "\"", "unique names");
  }
}

const TestSpec* CaseSpec::find_test(const std::string& name) const {
  const auto it = std::find_if(test.begin(), test.end(), [&](const TestSpec& t) { return t.name == name; });
  return it == test.end() ? nullptr : &*it;
}

std::vector<fem::TestModel> CaseSpec::models() const {
  std::vector<fem::TestModel> out;
  for (const auto& t : test) out.push_back(t.model(mesh, rig));
  return out;
}

// ---------------------------------------------------------------------------------------------------
// Builders from validated tables

TestKind test_kind(const io::Node& test) { return TestSpec::from_config(test).test_kind(); }

fem::MeshOptions build_mesh_options(const io::Node& mesh, const io::Node* over) {
  const MeshSpec m = MeshSpec::from_config(mesh);
  if (!over) return mesh_options(m, nullptr);
  return TestMeshSpec::from_config(*over).options(m);
}

fem::TestModel build_test(const io::Node& test, const io::Node& mesh, const io::Node* rig) {
  return TestSpec::from_config(test).model(MeshSpec::from_config(mesh), rig ? RigSpec::from_config(*rig) : RigSpec{});
}

std::unique_ptr<fem::Law> build_law(const io::Node& law) { return LawSpec::from_config(law).law(); }

fem::SolveOptions build_solver(const io::Node& s) { return SolverSpec::from_config(s).options(); }

void check_tests(const io::Node& root) {
  CaseSpec c;
  c.origin = Origin(root);
  for (const auto& t : root.array("test")) c.test.push_back(TestSpec::from_config(t));
  c.check_tests();
}

}  // namespace tricot::project
