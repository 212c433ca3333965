// The case schema and its builders (THEORY §5–§6). See case_config.hpp.
#include "tricot/project/case_spec.hpp"

#include <fmt/format.h>

#include <cmath>
#include <regex>
#include <set>

#include "schema.hpp"
#include "tricot/fem/corotational.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/neo_hookean.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/response_surface.hpp"

namespace tricot::project {

namespace {

std::string num(double x) { return io::to_toml(x); }

// fem's validate() names `test.<field>`, `mesh.<field>` or `material.<coefficient>` without a file:
// rethrow it at the line of the same key of `n` (the table's line when `n` has no such key).
[[noreturn]] void rethrow_at(const Node& n, const InputError& e, const std::string& key_override = {}) {
  if (!e.where().file.empty()) throw;  // already located in the file (called from a handler)
  std::string key = e.where().key;
  const auto dot = key.find('.');
  if (dot != std::string::npos) key = key.substr(dot + 1);
  if (!key_override.empty()) key = key_override;
  throw InputError(n.where(key), problem_of(e));
}

std::string join(const Strings& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// "C2W1" -> εC² εW; "C1" -> εC; "W3" -> εW³ (a general response surface's monomials).
std::vector<fem::Monomial> monomials(const Node& n, const char* key) {
  static const std::regex pattern(R"((?:C(\d+))?(?:W(\d+))?)");
  std::vector<fem::Monomial> out;
  const Strings& names = n.strings(key);
  for (std::size_t k = 0; k < names.size(); ++k) {
    std::smatch m;
    if (names[k].empty() || !std::regex_match(names[k], m, pattern))
      n.fail(key, fmt::format("monomial {} is not written C<p>W<q>", k + 1), "\"" + names[k] + "\"",
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
                "The specimen and its mesh. Only a quarter of the specimen is modelled (symmetry on x = 0 and\n"
                "y = 0, THEORY §6): the mesh covers width/2 × height/2 with nx × ny elements.",
                false, {}, {}};
  s.keys = {
      key("width", 110.0, "Full specimen width across the load (x), mm, > 0.", 0, 1e5),
      key("height", 110.0, "Full free length of the specimen between the grips (y), mm, > 0.", 0, 1e5),
      key("element", std::string("Q8"), "Element type: Q8 serendipity (the paper's) or Q4 bilinear.", -kInf, kInf,
          {"Q4", "Q8"}),
      key("nx", std::int64_t{10}, "Elements across the quarter's width.", 1, 2000),
      key("ny", std::int64_t{10}, "Elements along the quarter's height.", 1, 2000),
      key("grading", 1.0,
          "First (y = 0) over last (at the grip) element height, > 0; 1 = uniform, < 1 refines toward\n"
          "the grip where the clamp makes the field steep.",
          0, 1e3),
  };
  return s;
}

namespace {

SectionSpec test_mesh_section() {
  SectionSpec s{"mesh", "This test's own mesh: a non-zero (non-empty) value replaces the key of [mesh].", false, {}, {}};
  s.keys = {
      key("width", 0.0, "Full specimen width, mm; 0 = as in [mesh].", 0, 1e5),
      key("height", 0.0, "Full free length between the grips, mm; 0 = as in [mesh].", 0, 1e5),
      key("element", std::string(""), "Q4 or Q8; \"\" = as in [mesh]."),
      key("nx", std::int64_t{0}, "Elements across the quarter's width; 0 = as in [mesh].", 0, 2000),
      key("ny", std::int64_t{0}, "Elements along the quarter's height; 0 = as in [mesh].", 0, 2000),
      key("grading", 0.0, "First over last element height; 0 = as in [mesh].", 0, 1e3),
  };
  return s;
}

}  // namespace

io::SectionSpec law_section() {
  SectionSpec law{"law",
                  "The material law (THEORY §5). Forces are per unit reference width (N/mm): a knit's thickness\n"
                  "has no meaning, so every modulus below is a membrane modulus (stress × thickness).",
                  false, {}, {}};
  law.keys = {key("type", std::string("mooney_rivlin"),
                  "Which law: the table [law.<type>] below holds its coefficients; the other tables are ignored.",
                  -kInf, kInf,
                  {"mooney_rivlin", "neo_hookean", "corotational", "response_surface", "reference_fabric"})};

  SectionSpec mr{"mooney_rivlin",
                 "Incompressible Mooney–Rivlin, W = Σ C_ij (I1 − 3)^i (I2 − 3)^j (paper eq. 7), plane stress.",
                 false, {}, {}};
  // Default: the paper's validation set (docs/validation/laws-iso.md), a rubber-like S curve.
  Strings mr_names;
  Reals mr_values;
  for (const auto& t : fem::paper_mooney_rivlin_terms()) {
    mr_names.push_back(fmt::format("C{}{}", t.i, t.j));
    mr_values.push_back(t.C);
  }
  mr.keys = {
      key("terms", mr_names, "Names C<i><j> of the terms kept (i, j = 0..9, not both 0)."),
      key("values", mr_values, "C_ij of each term, N/mm, in the order of `terms`.", -1e6, 1e6),
  };
  SectionSpec nh{"neo_hookean", "Compressible neo-Hookean membrane (a helper law for tests).", false, {}, {}};
  nh.keys = {
      key("mu", 0.1, "Shear modulus μ, N/mm, > 0.", 0, 1e6),
      key("lambda", 0.2, "Lamé modulus λ, N/mm.", 0, 1e6),
  };
  SectionSpec co{"corotational",
                 "Corotational Eulerian law τ̂ = 𝔻 : ln U (THEORY §4): orthotropic linear on the logarithmic\n"
                 "strain in the material frame (course, wale), or isotropic.",
                 false, {}, {}};
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
  SectionSpec rs{"response_surface",
                 "Orthotropic response surface (paper eqs. 8/10, THEORY §5): forces per width along course and\n"
                 "wale as polynomials of the Green–Lagrange strains εC, εW along the material axes.",
                 false, {}, {}};
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
      key("shear_stiffness", 0.01, "In-plane shear stiffness G_s, N/mm, > 0 (a knit carries almost no shear).", 0,
          1e6),
  };
  const fem::ReferenceFabricParameters rp;
  SectionSpec rf{"reference_fabric",
                 "The reference knit of synthetic experiments (docs/theory/fabric.md §4): J-shaped course and\n"
                 "wale responses (linear, then exponential locking) and a coupling that stiffens under\n"
                 "combined stretch; deliberately outside the polynomial family. Strains: Green–Lagrange.",
                 false, {}, {}};
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
      key("G_s", rp.G_s, "In-plane shear stiffness, N/mm, > 0.", 0, 1e6),
  };
  law.sections = {mr, nh, co, rs, rf};
  return law;
}

io::SectionSpec solver_section() {
  SectionSpec s{"solver", "Newton–Raphson with line search and load-step cutback (THEORY §4–§7).", false, {}, {}};
  const fem::SolveOptions d;
  s.keys = {
      key("tolerance", d.tolerance, "Newton stops when the free residual ≤ tolerance × the reaction force, > 0.", 0,
          1),
      key("max_iterations", std::int64_t{d.max_iterations}, "Newton iterations per (sub)step.", 1, 200),
      key("line_search", d.line_search, "Backtracking line search on the residual norm."),
      key("max_cutbacks", std::int64_t{d.max_cutbacks}, "Halvings of a failed step before giving up.", 0, 30),
  };
  return s;
}

io::SectionSpec test_section() {
  SectionSpec s{"test",
                "One test of the case: its output goes to DIR/<name>/ (steps.csv, step_NNNN.vtu, force.png).",
                true, {}, {}};
  s.keys = {
      key("name", std::string("uniaxial"), "Test name: letters, digits, '_', '-' and '.' (a folder name)."),
      key("kind", std::string("uniaxial"),
          "uniaxial: grip on top, side edge free. biaxial: side edge on a guide (the paper's\n"
          "biaxial-induced test). homogeneous: sliding grip, a uniform field. simple_shear: the law alone\n"
          "at F = [[1, γ], [0, 1]] for γ in the step list (one element; writes gamma, s11, s22, s12).",
          -kInf, kInf, {"uniaxial", "biaxial", "homogeneous", "simple_shear"}),
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
          "biaxial guide; homogeneous takes either.",
          -kInf, kInf, {"free", "guide"}),
      key("guide", Reals{},
          "Guide displacement u_x of the side edge, mm (negative narrows the specimen): one value, reached\n"
          "in proportion to the load, or one per step; [] = 0, the width held.",
          -1e5, 1e5),
      key("loads", Reals{},
          "The step list, strictly increasing (mm or N as `control` says; γ for simple_shear). When\n"
          "empty, `load_max` and `steps` make a uniform list.",
          -1e9, 1e9, {}, true),
      key("load_max", 10.0, "Last load of the uniform list (mm, N or γ), > 0; used when `loads` is empty.", 0, 1e9),
      key("steps", std::int64_t{10}, "Steps of the uniform list: load_max · k / steps for k = 1 … steps.", 1, 100000),
  };
  s.sections = {test_mesh_section()};
  return s;
}

io::SectionSpec case_schema() {
  SectionSpec root{"",
                   "tricot simulate: a case file. Finite-element models of tests on a knitted-fabric specimen\n"
                   "(plane-stress membrane, quarter specimen, THEORY §4–§6). Units: mm, N, N/mm, degrees.",
                   false, {}, {}};
  root.sections = {mesh_section(), law_section(), solver_section(), test_section()};
  return root;
}

// ---------------------------------------------------------------------------------------------------
// Builders

TestKind test_kind(const io::Node& test) {
  const std::string& k = test.string("kind");
  if (k == "biaxial") return TestKind::biaxial;
  if (k == "homogeneous") return TestKind::homogeneous;
  if (k == "simple_shear") return TestKind::simple_shear;
  return TestKind::uniaxial;
}

fem::MeshOptions build_mesh_options(const io::Node& mesh, const io::Node* over) {
  auto real = [&](const char* k) -> std::pair<double, const Node*> {
    if (over && over->real(k) != 0) return {over->real(k), over};
    return {mesh.real(k), &mesh};
  };
  auto integer = [&](const char* k) -> int {
    if (over && over->integer(k) != 0) return static_cast<int>(over->integer(k));
    return static_cast<int>(mesh.integer(k));
  };
  fem::MeshOptions o;
  for (const char* k : {"width", "height", "grading"}) {
    const auto [v, from] = real(k);
    if (!(v > 0)) from->fail(k, "must be positive", num(v), "> 0");
  }
  o.width = real("width").first / 2;
  o.height = real("height").first / 2;
  o.grading = real("grading").first;
  o.nx = integer("nx");
  o.ny = integer("ny");
  if (over && !over->string("element").empty() && over->string("element") != "Q4" && over->string("element") != "Q8")
    over->fail("element", "not an element type", "\"" + over->string("element") + "\"", "Q4, Q8 or \"\"");
  const std::string& type = over && !over->string("element").empty() ? over->string("element") : mesh.string("element");
  o.type = type == "Q4" ? fem::ElementType::Q4 : fem::ElementType::Q8;
  try {
    o.validate();
  } catch (const InputError& e) {
    rethrow_at(over ? *over : mesh, e);
  }
  return o;
}

namespace {

std::vector<double> step_list(const Node& test) {
  const Reals& loads = test.reals("loads");
  if (!loads.empty()) return loads;
  const double last = test.real("load_max");
  if (!(last > 0)) test.fail("load_max", "must be positive (or give `loads`)", num(last), "> 0");
  const auto n = test.integer("steps");
  std::vector<double> l(static_cast<std::size_t>(n));
  for (std::int64_t k = 1; k <= n; ++k) l[k - 1] = last * double(k) / double(n);
  return l;
}

// A unit square of one element: nodes at the corners (and mid-sides for Q8), edges as a quarter mesh.
fem::Mesh unit_element(fem::ElementType type) {
  fem::MeshOptions o;
  o.width = o.height = 1;
  o.nx = o.ny = 1;
  o.type = type;
  return fem::make_quarter_mesh(o);
}

}  // namespace

fem::TestModel build_test(const io::Node& test, const io::Node& mesh) {
  fem::TestModel t;
  t.name = test.string("name");
  const TestKind kind = test_kind(test);
  const fem::MeshOptions mo = build_mesh_options(mesh, &test.section("mesh"));
  t.loads = step_list(test);
  t.material_angle = test.real("material_angle");

  if (kind == TestKind::simple_shear) {
    // One element with every node prescribed: the law's homogeneous response (THEORY §4 validation).
    t.mesh = unit_element(mo.type);
    t.grip_holds_x = false;
    t.side = fem::SideEdge::free;
    if (test.string("control") != "displacement")
      test.fail("control", "simple_shear prescribes the shear γ", "\"" + test.string("control") + "\"",
                "displacement");
    return t;
  }

  t.control = test.string("control") == "force" ? fem::GripControl::force : fem::GripControl::displacement;
  t.grip_holds_x = test.boolean("grip_holds_x");
  t.grip_follows_guide = test.boolean("grip_follows_guide");
  const std::string& side = test.string("side");
  switch (kind) {
    case TestKind::uniaxial:
      if (side != "free")
        test.fail("side", "a uniaxial test has a free side edge; use kind = \"biaxial\" for a guide",
                  "\"" + side + "\"", "free");
      t.side = fem::SideEdge::free;
      break;
    case TestKind::biaxial:
      if (test.given("side") && side != "guide")
        test.fail("side", "a biaxial test has its side edge on a guide", "\"" + side + "\"", "guide");
      t.side = fem::SideEdge::guide;
      break;
    case TestKind::homogeneous:
      if (test.given("grip_holds_x") && t.grip_holds_x)
        test.fail("grip_holds_x", "a homogeneous test needs a sliding grip", "true", "false");
      t.grip_holds_x = false;
      t.side = side == "guide" ? fem::SideEdge::guide : fem::SideEdge::free;
      break;
    case TestKind::simple_shear: break;
  }
  if (t.side == fem::SideEdge::guide) {
    t.guide = test.reals("guide");
    if (t.guide.empty()) t.guide = {0.0};
    for (std::size_t k = 0; k < t.guide.size(); ++k)
      if (t.guide[k] <= -mo.width)
        test.fail("guide", fmt::format("guide value {} would pull the side edge past the symmetry axis", k + 1),
                  num(t.guide[k]), fmt::format("> -{} mm, half the width", num(mo.width)));
  } else if (!test.reals("guide").empty()) {
    test.fail("guide", "guide values given but the side edge is free", io::to_toml(test.reals("guide")),
              "none, or side = \"guide\"");
  }
  if (t.control == fem::GripControl::force && t.side == fem::SideEdge::guide)
    test.fail("control", "force control is for a free side edge (uniaxial)", "\"force\"", "displacement");

  const Reals& loads = t.loads;
  if (!(loads.front() > 0))
    test.fail(test.reals("loads").empty() ? "load_max" : "loads", "the first load must be positive",
              num(loads.front()), "> 0");
  t.mesh = fem::make_quarter_mesh(mo);
  try {
    t.validate();
  } catch (const InputError& e) {
    rethrow_at(test, e);
  }
  return t;
}

std::unique_ptr<fem::Law> build_law(const io::Node& law) {
  const std::string& type = law.string("type");
  const Node& n = law.section(type);
  try {
    if (type == "mooney_rivlin") {
      const Strings& names = n.strings("terms");
      const Reals& values = n.reals("values");
      if (names.size() != values.size())
        n.fail("values", "one value per term", fmt::format("{} values", values.size()),
               fmt::format("{} as in terms", names.size()));
      std::vector<fem::MooneyRivlinTerm> terms;
      for (std::size_t k = 0; k < names.size(); ++k) {
        const std::string& s = names[k];
        if (s.size() != 3 || s[0] != 'C' || !std::isdigit(static_cast<unsigned char>(s[1])) ||
            !std::isdigit(static_cast<unsigned char>(s[2])) || s == "C00")
          n.fail("terms", fmt::format("term {} is not a name C<i><j>", k + 1), "\"" + s + "\"",
                 "C10, C01, C20, C21, C03, …");
        terms.push_back({s[1] - '0', s[2] - '0', values[k]});
      }
      return std::make_unique<fem::MooneyRivlin>(std::move(terms));
    }
    if (type == "neo_hookean") {
      if (!(n.real("mu") > 0)) n.fail("mu", "must be positive", num(n.real("mu")), "> 0");
      return std::make_unique<fem::NeoHookean>(n.real("mu"), n.real("lambda"));
    }
    if (type == "corotational") {
      if (n.string("moduli") == "isotropic") {
        for (const char* k : {"G", "K"})
          if (!(n.real(k) > 0)) n.fail(k, "must be positive", num(n.real(k)), "> 0");
        return std::make_unique<fem::CorotationalOrthotropic>(
            fem::CorotationalOrthotropic::isotropic(n.real("G"), n.real("K")));
      }
      return std::make_unique<fem::CorotationalOrthotropic>(n.real("D11"), n.real("D22"), n.real("D12"),
                                                            n.real("D66"));
    }
    if (type == "response_surface") {
      const double G_s = n.real("shear_stiffness");
      if (!(G_s > 0)) n.fail("shear_stiffness", "must be positive", num(G_s), "> 0");
      const std::string& preset = n.string("preset");
      fem::ResponseSurface rs = preset == "general"
                                    ? fem::ResponseSurface(monomials(n, "course"), monomials(n, "wale"), G_s)
                                    : fem::ResponseSurface::preset(preset, G_s);
      const Reals& c = n.reals("coefficients");
      if (!c.empty()) {
        if (c.size() != static_cast<std::size_t>(rs.coefficients().size()))
          n.fail("coefficients", "one coefficient per term of the law", fmt::format("{} values", c.size()),
                 fmt::format("{} ({})", rs.coefficients().size(), join(rs.coefficient_names())));
        rs.set_coefficients(Eigen::Map<const Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size())));
      }
      return std::make_unique<fem::ResponseSurface>(std::move(rs));
    }
    if (type == "reference_fabric") {
      fem::ReferenceFabricParameters p;
      p.k_C = n.real("k_C"), p.k_CL = n.real("k_CL"), p.eps_CL = n.real("eps_CL"), p.s_CL = n.real("s_CL");
      p.k_W = n.real("k_W"), p.k_WL = n.real("k_WL"), p.eps_WL = n.real("eps_WL"), p.s_WL = n.real("s_WL");
      p.k_X = n.real("k_X"), p.G_s = n.real("G_s");
      return std::make_unique<fem::ReferenceFabric>(p);
    }
  } catch (const InputError& e) {
    // fem names `material.<coefficient>`: point at the key of this table that holds it.
    std::string k;
    if (type == "mooney_rivlin") k = "values";
    if (type == "response_surface") {
      const std::string& fk = e.where().key;
      k = fk.ends_with("G_s") ? "shear_stiffness" : fk.ends_with("monomials") ? "course" : "coefficients";
    }
    rethrow_at(n, e, k);
  }
  law.fail("type", "unknown law", "\"" + type + "\"");  // the schema's choices make this unreachable
}

fem::SolveOptions build_solver(const io::Node& s) {
  fem::SolveOptions o;
  o.tolerance = s.real("tolerance");
  if (!(o.tolerance > 0)) s.fail("tolerance", "must be positive", num(o.tolerance), "> 0");
  o.max_iterations = static_cast<int>(s.integer("max_iterations"));
  o.line_search = s.boolean("line_search");
  o.max_cutbacks = static_cast<int>(s.integer("max_cutbacks"));
  try {
    o.validate();
  } catch (const InputError& e) {
    rethrow_at(s, e);
  }
  return o;
}

void check_tests(const io::Node& root) {
  const auto& tests = root.array("test");
  if (tests.empty()) root.fail("test", "the case has no [[test]]", "none", "at least one [[test]] table");
  std::set<std::string> seen;
  for (const auto& t : tests) {
    const std::string& name = t.string("name");
    const bool ok = !name.empty() && name != "." && name != ".." &&
                    name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") ==
                        std::string::npos;
    if (!ok) t.fail("name", "not usable as a folder name", "\"" + name + "\"", "letters, digits, '_', '-', '.'");
    if (!seen.insert(name).second) t.fail("name", "two tests have this name", "\"" + name + "\"", "unique names");
  }
}

}  // namespace tricot::project
