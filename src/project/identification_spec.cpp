// The project file of `tricot identify` (see identification.hpp): its schema ([experiment],
// [[parameter]], [data], [identify] beside the case's tables) and the builder of the objective.
#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "schema.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/identifiability.hpp"
#include "tricot/ident/objective.hpp"
#include "tricot/ident/surface_error.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/identification.hpp"

namespace tricot::project {

namespace {

namespace fs = std::filesystem;

SectionSpec experiment_section() {
  SectionSpec s{"experiment",
                "The measurements (`tricot synth` writes such a folder): DIR/<test>/forces.csv (step, load,\n"
                "edge_displacement, edge_force) and optionally DIR/<test>/field.csv (step, id, x, y, u, v),\n"
                "one sub-folder per [[test]] of this file, with the same steps.",
                false, {}, {}};
  s.keys = {
      key("dir", std::string("experiment"), "The experiment folder, relative to this file."),
      key("field_kind", std::string("cumulative"),
          "What field.csv holds. cumulative: u(X, t_k) of material points (x, y = reference position).\n"
          "incremental: displacement since the previous step at points fixed in the images (THEORY §7).",
          -kInf, kInf, {"cumulative", "incremental"}),
      key("sigma_edge_displacement", 0.0,
          "Measurement σ of the grip displacement, mm; 0 = unknown (the group is scaled by its RMS,\n"
          "THEORY §2). Given σ make f a χ²/2 and the standard errors real ones (THEORY §8).",
          0, 1e6),
      key("sigma_edge_force", 0.0, "Measurement σ of the grip force, N; 0 = unknown.", 0, 1e9),
      key("sigma_field", 0.0, "Measurement σ of u and v, mm; 0 = unknown.", 0, 1e6),
      key("sigma_from_truth", false,
          "Take every test's σ from DIR/truth.json (the noise tricot synth added); replaces the three above."),
  };
  return s;
}

SectionSpec parameter_section() {
  SectionSpec s{"parameter",
                "One identified coefficient of [law] (the others keep their [law] values). LM works in\n"
                "x = J / scale: with scale = 0 the steps are relative to the start, as the paper's\n"
                "J_{i+1} = J_i + t_i·J_i (THEORY §3).",
                true, {}, {}};
  s.keys = {
      key("name", std::string("C10"), "The coefficient's name in the law (e.g. C10, C03; a1 … for a response surface)."),
      key("start", 0.1,
          "Start value, in the coefficient's units. Not given: the value in [law], so that [law] can\n"
          "hold the start point."),
      key("scale", 0.0,
          "Typical size of the coefficient, > 0; 0 = |start|. A zero start needs a scale.", 0, 1e12),
      key("bounds", io::Reals{}, "[lower, upper] bounds on the coefficient; [] = none."),
  };
  return s;
}

SectionSpec data_section() {
  const ident::DataWeights d;
  SectionSpec s{"data",
                "Which data enter the objective f, eq. (1), and their weights w_g (THEORY §2); 0 leaves a\n"
                "kind of data out. Each group is normalised by its σ or RMS, so weights compare kinds.",
                false, {}, {}};
  s.keys = {
      key("edge_displacement", d.edge_displacement,
          "Grip displacement (the cross-head), ≥ 0; used for force-controlled tests only.", 0, 1e12),
      key("edge_force", d.edge_force, "Grip force, ≥ 0; used for displacement-controlled tests only.", 0, 1e12),
      key("field", d.field, "Displacements u, v at the field points, ≥ 0.", 0, 1e12),
      key("field_uv", d.field_uv, "u and v in one group with one scale (false: a group each)."),
      key("field_sigma", std::string("group"),
          "σ of the field values. group: [experiment] sigma_field (or the RMS); per_point: the sigma_u,\n"
          "sigma_v columns of field.csv (tricot experiment writes the DIC's σ), so that the covariance\n"
          "reflects the DIC noise (THEORY §8).",
          -kInf, kInf, {"group", "per_point"}),
  };
  return s;
}

SectionSpec identify_section() {
  const ident::IdentifyOptions o;
  SectionSpec s{"identify", "Levenberg–Marquardt and its stopping criteria (THEORY §3, paper eqs. 2 and 3).", false, {},
                {}};
  s.keys = {
      key("epsilon", o.epsilon, "Eq. (2): stop when f < epsilon; 0 = off. Paper: 1e-12.", 0, 1),
      key("delta", o.delta,
          "Eq. (3): stop when an accepted step changes no coefficient by more than delta (relative),\n"
          "in (0, 1). Paper: 1e-5.",
          0, 1),
      key("function_tolerance", o.function_tolerance, "Stop when a step changes f by less than this fraction of f; 0 = off.", 0, 1),
      key("gradient_tolerance", o.gradient_tolerance, "Stop when the gradient's max-norm (LM units) is below this; 0 = off.", 0, 1e12),
      key("max_iterations", std::int64_t{o.max_iterations},
          "LM iterations in all (accepted and rejected, stability restarts included).", 1, 100000),
      key("stability_test", o.stability_test,
          "The paper's stability test: after convergence, f with each coefficient scaled by (1 ± eta);\n"
          "LM restarts from a lower one."),
      key("stability_eta", o.stability_eta, "η of the stability test, in (0, 1).", 0, 1),
      key("max_restarts", std::int64_t{o.max_restarts}, "Stability restarts before giving up (termination `unstable`).", 0, 1000),
      key("jacobian", std::string("exact"),
          "exact: from the FE sensitivities (THEORY §7). finite_difference: one perturbed FE run per\n"
          "coefficient (two when central), in parallel threads (the paper's way).",
          -kInf, kInf, {"exact", "finite_difference"}),
      key("difference", std::string("forward"), "finite_difference only: forward or central.", -kInf, kInf,
          {"forward", "central"}),
      key("fd_step", o.fd_step, "finite_difference only: step h_k = fd_step · scale_k, in (0, 0.1].", 0, 0.1),
      key("threads", std::int64_t{o.threads}, "Threads for tests and finite-difference columns; 0 = all cores.", 0, 1024),
      key("initial_trust_region_radius", o.initial_trust_region_radius, "LM's first trust-region radius (1/μ₀, LM units), > 0.",
          0, 1e16),
  };
  return s;
}

// `e.what()` is "FILE:LINE: KEY: problem …" with file and line empty for the library's errors;
// rethrow it at `key` of node `n` of the project file.
[[noreturn]] void relocate(const InputError& e, const Node& n, const std::string& key) {
  std::string s = e.what();
  const std::string k = e.where().key;
  if (!k.empty() && s.rfind(k + ": ", 0) == 0) s = s.substr(k.size() + 2);
  throw InputError(n.where(key), s);
}

std::vector<ident::Parameter> build_parameters(const Node& root, const fem::Law& law) {
  const auto& nodes = root.array("parameter");
  if (nodes.empty())
    root.fail("parameter", "the project identifies nothing", "no [[parameter]]", "one [[parameter]] per coefficient");
  const std::vector<std::string> names = law.coefficient_names();
  const Eigen::VectorXd c = law.coefficients();
  std::vector<ident::Parameter> out;
  for (const Node& p : nodes) {
    const std::string& name = p.string("name");
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
      const std::string hint = io::closest_name(name, names);
      std::string all;
      for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
      p.fail("name",
             fmt::format("not a coefficient of the {} law in [law]{}", law.name(),
                         hint.empty() ? "" : "; did you mean '" + hint + "'?"),
             "\"" + name + "\"", all);
    }
    for (const auto& q : out)
      if (q.name == name) p.fail("name", "this coefficient is identified twice", "\"" + name + "\"", "unique names");
    ident::Parameter x;
    x.name = name;
    x.start = p.given("start") ? p.real("start") : c(it - names.begin());
    x.scale = p.real("scale");
    if (x.start == 0 && x.scale == 0)
      p.fail("scale",
             fmt::format("parameter {} starts at 0 and has no scale: LM's steps are relative to the start", name),
             "0.0", "> 0, the size of a typical change of " + name);
    const io::Reals& b = p.reals("bounds");
    if (!b.empty()) {
      if (b.size() != 2) p.fail("bounds", "two values: [lower, upper]", io::to_toml(b), "[] or [lower, upper]");
      if (!(b[0] < b[1])) p.fail("bounds", "lower must be below upper", io::to_toml(b), "lower < upper");
      if (x.start < b[0] || x.start > b[1])
        p.fail(p.given("start") ? "start" : "bounds", fmt::format("the start of {} is outside its bounds", name),
               io::to_toml(x.start), io::to_toml(b));
      x.lower = b[0];
      x.upper = b[1];
    }
    out.push_back(x);
  }
  return out;
}


}  // namespace

IdentifyTable IdentifyTable::from_config(const io::Node& s) {
  IdentifyTable t;
  t.origin = Origin(s);
  t.epsilon = s.real("epsilon");
  t.delta = s.real("delta");
  t.function_tolerance = s.real("function_tolerance");
  t.gradient_tolerance = s.real("gradient_tolerance");
  t.max_iterations = static_cast<int>(s.integer("max_iterations"));
  t.stability_test = s.boolean("stability_test");
  t.stability_eta = s.real("stability_eta");
  t.max_restarts = static_cast<int>(s.integer("max_restarts"));
  t.jacobian = s.string("jacobian");
  t.difference = s.string("difference");
  t.fd_step = s.real("fd_step");
  t.threads = static_cast<int>(s.integer("threads"));
  t.initial_trust_region_radius = s.real("initial_trust_region_radius");
  return t;
}

ident::IdentifyOptions IdentifyTable::options() const {
  ident::IdentifyOptions o;
  o.epsilon = epsilon;
  o.delta = delta;
  o.function_tolerance = function_tolerance;
  o.gradient_tolerance = gradient_tolerance;
  o.max_iterations = max_iterations;
  o.stability_test = stability_test;
  o.stability_eta = stability_eta;
  o.max_restarts = max_restarts;
  if (jacobian != "exact" && jacobian != "finite_difference")
    origin.fail("jacobian", "unknown Jacobian", "\"" + jacobian + "\"", "exact or finite_difference");
  o.jacobian = jacobian == "exact" ? ident::JacobianMode::exact : ident::JacobianMode::finite_difference;
  if (difference != "forward" && difference != "central")
    origin.fail("difference", "unknown difference", "\"" + difference + "\"", "forward or central");
  o.difference = difference == "central" ? ident::Difference::central : ident::Difference::forward;
  o.fd_step = fd_step;
  o.threads = threads;
  o.initial_trust_region_radius = initial_trust_region_radius;
  try {
    o.validate();
  } catch (const InputError& e) {
    if (!origin.owns(e)) throw;
    origin.rethrow(e);  // ident names the keys of [identify]
  }
  return o;
}

SectionSpec eq9_section() {
  const ident::StrainDomain d;
  SectionSpec s{"eq9",
                "Eq. (9) in result.json (THEORY §9, paper Table 5): the mean relative distance between the\n"
                "identified and the measured force per unit width at the experimental points (each step of a\n"
                "test pulled along wale, material_angle 0, or course, 90: grip force / full width against the\n"
                "centre strain of the measured field), over all points and over the practical domain.",
                false, {}, {}};
  s.keys = {
      key("practical_course", io::Reals{d.eC_min, d.eC_max}, "[min, max] Green–Lagrange εC of practical use (paper: 60–100 %).",
          -1, 100),
      key("practical_wale", io::Reals{d.eW_min, d.eW_max}, "[min, max] Green–Lagrange εW of practical use (paper: 20–40 %).",
          -1, 100),
      key("nearest", std::int64_t{6}, "Field points nearest the centre that the centre strain is fitted on (affine), ≥ 3.",
          3, 1000000),
  };
  return s;
}

SectionSpec identifiability_section() {
  const ident::IdentifiabilityOptions o;
  SectionSpec s{"identifiability",
                "result.json's \"identifiability\" (THEORY §8, beyond the paper): relative standard errors, the\n"
                "least identifiable direction and each test's share of the information, from ∂r/∂J at the answer.",
                false, {}, {}};
  s.keys = {key("pinned_relative_error", o.pinned_relative_error,
                "A coefficient is pinned down when its relative standard error is below this, > 0.", 0, 1e6)};
  return s;
}

io::SectionSpec identify_schema() {
  io::SectionSpec root = case_schema();
  root.help =
      "tricot identify: a project file. The case (specimen, law, solver, tests) models the experiment;\n"
      "LM fits the [[parameter]] coefficients of [law] to the data of [experiment] (THEORY §1–§3).\n"
      "Units: mm, N, N/mm, degrees.";
  root.sections.push_back(experiment_section());
  root.sections.push_back(parameter_section());
  root.sections.push_back(data_section());
  root.sections.push_back(identify_section());
  root.sections.push_back(eq9_section());
  root.sections.push_back(identifiability_section());
  return root;
}

namespace {

// [eq9]: the practical domain, checked against the experimental points of the data (a domain that
// holds none of a surface's points is an error located at its key, naming the data's strain range).
void read_eq9(const Node& n, Project& P) {
  for (const char* k : {"practical_course", "practical_wale"}) {
    const io::Reals& r = n.reals(k);
    if (r.size() != 2 || r[0] > r[1])
      n.fail(k, "not a strain interval", fmt::format("{} values", r.size()), "[min, max] with min <= max");
  }
  P.eq9_practical.eC_min = n.reals("practical_course")[0], P.eq9_practical.eC_max = n.reals("practical_course")[1];
  P.eq9_practical.eW_min = n.reals("practical_wale")[0], P.eq9_practical.eW_max = n.reals("practical_wale")[1];
  P.eq9_nearest = static_cast<int>(n.integer("nearest"));
  // A domain the user gave must meet the data; the default one may not (then "practical" is null).
  if (!n.given("practical_course") && !n.given("practical_wale")) return;
  const auto points = eq9_points(*P.objective, P.eq9_nearest);
  for (int f = 0; f < 2; ++f) {
    if (points[f].empty()) continue;
    try {
      (void)ident::eq9_error(points[f], [](double, double) { return 0.0; }, P.eq9_practical);
    } catch (const InputError& e) {
      if (e.where().key != "eq9.practical") throw;
      const std::string what = std::string(e.what()).substr(e.where().key.size() + 2);
      n.fail(f == 0 ? "practical_course" : "practical_wale",
             std::string(f == 0 ? "course" : "wale") + " surface: " + what);
    }
  }
}

}  // namespace

std::array<std::vector<ident::SurfacePoint>, 2> eq9_points(const ident::Objective& objective, int nearest) {
  std::array<std::vector<ident::SurfacePoint>, 2> out;
  const auto& models = objective.models();
  const auto& tests = objective.experiment().tests;
  for (std::size_t t = 0; t < tests.size() && t < models.size(); ++t) {
    const auto p = ident::test_surface_points(models[t], tests[t], nearest);
    if (!p) continue;
    auto& dst = out[p->force == ident::SurfaceForce::course ? 0 : 1];
    dst.insert(dst.end(), p->points.begin(), p->points.end());
  }
  return out;
}

Project build_project(const io::Node& root, const fs::path& base) {
  Project P;
  const CaseSpec spec = CaseSpec::from_config(root);
  spec.check_tests();
  P.law = spec.law.law();
  P.solver = spec.solver.options();
  std::vector<std::string> names;
  for (const auto& t : spec.test) {
    if (t.test_kind() == TestKind::simple_shear)
      t.origin.fail("kind", "identify needs FE tests", "\"simple_shear\"", "uniaxial, biaxial, homogeneous or rig");
    P.models.push_back(t.model(spec.mesh, spec.rig));
    names.push_back(t.name);
  }
  std::vector<ident::Parameter> parameters = build_parameters(root, *P.law);
  P.options = IdentifyTable::from_config(root.section("identify")).options();

  // The experiment.
  const Node& ex = root.section("experiment");
  const fs::path dir = base / ex.string("dir");
  if (!fs::is_directory(dir))
    throw FileError(ex.where("dir"), "experiment folder not found", "\"" + dir.string() + "\"",
                    "a folder written by tricot synth, relative to the project file");
  const auto kind = ex.string("field_kind") == "incremental" ? ident::FieldKind::incremental
                                                             : ident::FieldKind::cumulative;
  ident::Experiment experiment = read_experiment(dir, names, kind);
  P.truth = read_truth(dir);
  const bool has_field = std::any_of(experiment.tests.begin(), experiment.tests.end(),
                                     [](const ident::TestData& d) { return d.has_field(); });
  if (P.truth && has_field && P.truth->field_kind != kind)
    ex.fail("field_kind", fmt::format("{}/truth.json says the field data are {}", dir.string(),
                                      ident::to_string(P.truth->field_kind)),
            "\"" + ex.string("field_kind") + "\"", ident::to_string(P.truth->field_kind));
  for (auto& d : experiment.tests) {
    if (ex.boolean("sigma_from_truth")) {
      if (!P.truth)
        throw FileError(ex.where("sigma_from_truth"), "the experiment has no truth.json to take σ from",
                        (dir / kTruthFile).string());
      const Truth::Test* t = P.truth->find(d.name);
      if (!t) ex.fail("sigma_from_truth", "truth.json has no test '" + d.name + "'");
      d.sigma = t->sigma;
    } else {
      d.sigma = {ex.real("sigma_edge_displacement"), ex.real("sigma_edge_force"), ex.real("sigma_field")};
    }
  }

  const Node& dn = root.section("data");
  for (auto& d : experiment.tests)
    if (dn.string("field_sigma") != "per_point") {
      d.sigma_u.resize(0, 0), d.sigma_v.resize(0, 0);
    } else if (d.has_field() && d.sigma_u.size() == 0) {
      dn.fail("field_sigma", "field.csv of test '" + d.name + "' has no sigma_u, sigma_v columns", "\"per_point\"",
              "a field.csv written by tricot experiment");
    }
  ident::ObjectiveOptions oo;
  oo.weights.edge_displacement = dn.real("edge_displacement");
  oo.weights.edge_force = dn.real("edge_force");
  oo.weights.field = dn.real("field");
  oo.weights.field_uv = dn.boolean("field_uv");
  oo.solver = P.solver;
  oo.threads = P.options.threads;
  try {
    P.objective = std::make_unique<ident::Objective>(P.models, experiment, *P.law, parameters, oo);
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    const std::string& k = e.where().key;
    if (k == "data") relocate(e, dn, "");
    throw InputError({root.file(), 0, k}, std::string(e.what()).substr(k.empty() ? 0 : k.size() + 2));
  }
  read_eq9(root.section("eq9"), P);
  P.identifiability.pinned_relative_error = root.section("identifiability").real("pinned_relative_error");
  if (!(P.identifiability.pinned_relative_error > 0))
    root.section("identifiability").fail("pinned_relative_error", "must be positive",
                                         fmt::format("{}", P.identifiability.pinned_relative_error), "> 0");
  return P;
}

}  // namespace tricot::project
