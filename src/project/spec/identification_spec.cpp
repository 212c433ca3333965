// The project file of `tricot identify` (see identification.hpp): its schema ([experiment],
// [[parameter]], [data], [identify] beside the case's tables) and the builder of the objective.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "spec/schema.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/identifiability.hpp"
#include "tricot/ident/stability_barrier.hpp"
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
                false,
                {},
                {}};
  s.keys = {
      key("dir", std::string("experiment"), "The experiment folder, relative to this file."),
      key("field_kind", std::string("cumulative"),
          "What field.csv holds. cumulative: u(X, t_k) of material points (x, y = reference position).\n"
          "incremental: displacement since the previous step at points fixed in the images (docs/theory.md §7).",
          -kInf, kInf, {"cumulative", "incremental"}),
      key("sigma_edge_displacement", 0.0,
          "Measurement σ of the grip displacement, mm; 0 = unknown (the group is scaled by its RMS,\n"
          "docs/theory.md §2). Given σ make f a χ²/2 and the standard errors real ones (docs/theory.md §8).",
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
                "J_{i+1} = J_i + t_i·J_i (docs/theory.md §3).",
                true,
                {},
                {}};
  s.keys = {
      key("name", std::string("C10"),
          "The coefficient's name in the law (e.g. C10, C03; a1 … for a response surface), or\n"
          "\"<test>.force_scale\": that test's specimen force scale k, its grip force being k times the law's\n"
          "(displacement-controlled tests). Repeats of one fabric differ in stiffness (density, width, yarn):\n"
          "give each repeat but one per direction a scale, and the law is the reference repeat's, the\n"
          "scales its repeats' spread (docs/theory.md §2)."),
      key("start", 0.1,
          "Start value, in the coefficient's units. Not given: the value in [law], so that [law] can\n"
          "hold the start point (1 for a force scale)."),
      key("scale", 0.0, "Typical size of the coefficient, > 0; 0 = |start|. A zero start needs a scale.", 0, 1e12),
      key("bounds", io::Reals{},
          "[lower, upper] bounds on the coefficient; [] = none. A coefficient that LM's steps keep pushing\n"
          "onto its bound, where f decreases out of the box, is held there (the log says so) and LM steps in\n"
          "the others; it is released where f decreases into the box again."),
  };
  return s;
}

SectionSpec data_section() {
  const ident::DataWeights d;
  SectionSpec s{"data",
                "Which data enter the objective f, eq. (1), and their weights w_g (docs/theory.md §2); 0 leaves a\n"
                "kind of data out. Each group is normalised by its σ or RMS, so weights compare kinds.",
                false,
                {},
                {}};
  s.keys = {
      key("edge_displacement", d.edge_displacement,
          "Grip displacement (the cross-head), ≥ 0; used for force-controlled tests only.", 0, 1e12),
      key("edge_force", d.edge_force, "Grip force, ≥ 0; used for displacement-controlled tests only.", 0, 1e12),
      key("field", d.field, "Displacements u, v at the field points, ≥ 0.", 0, 1e12),
      key("field_uv", d.field_uv, "u and v in one group with one scale (false: a group each)."),
      key("weighting", std::string("scaled"),
          "How the weights act. scaled: eq. (1), each group divided by its size and by its σ (or RMS), so that\n"
          "weights compare kinds of data. fixed: the weights are absolute, per value, in 1/unit² of the data\n"
          "(f = ½ Σ w Σ (y − y*)², e.g. edge_force = 1 per N², field = 100 per mm²), as a published objective\n"
          "has them; standard errors then come from the residuals, not from σ.",
          -kInf, kInf, {"scaled", "fixed"}),
      key("field_sigma", std::string("group"),
          "σ of the field values. group: [experiment] sigma_field (or the RMS); per_point: the sigma_u,\n"
          "sigma_v columns of field.csv (tricot experiment writes the DIC's σ), so that the covariance\n"
          "reflects the DIC noise (docs/theory.md §8).",
          -kInf, kInf, {"group", "per_point"}),
      key("domain_course", io::Reals{},
          "[min, max] Green–Lagrange εC of a domain-restricted identification (paper §4.3.2): a test pulled\n"
          "along wale is kept when its held εC (centre, first step) is in it; a test pulled along course\n"
          "keeps its steps up to the last with centre εC <= max. Unset: no restriction across/along course.",
          -1, 100),
      key("domain_wale", io::Reals{},
          "[min, max] εW of the restriction, as domain_course with the two directions swapped.", -1, 100),
      key("domain_weight", 0.0,
          "0: the data outside domain_course x domain_wale are left out (a restricted identification). In (0, 1]:\n"
          "every test and step is kept, and the steps a restriction would leave out weigh this much (a\n"
          "weighted identification, paper §4.3.2). Needs domain_course or domain_wale.",
          0, 1),
  };
  return s;
}

SectionSpec design_section() {
  SectionSpec s{"design",
                "result.json's \"design\" (beyond the paper): which added test would help most. For each pull\n"
                "direction of the rig tests, the first such test held at each candidate transverse strain is\n"
                "simulated with the identified law; its sensitivities are added to the information matrix, and\n"
                "the candidates are ranked (D-optimal: the largest det; A-optimal: the smallest mean variance).",
                false,
                {},
                {}};
  s.keys = {
      key("transverse_strains", io::Reals{},
          "Candidate held strains across the pull (Green–Lagrange), e.g. [0.1, 0.3, 0.85].", -0.4, 10),
      key("criterion", std::string("d_optimal"), "d_optimal or a_optimal.", -kInf, kInf, {"d_optimal", "a_optimal"})};
  return s;
}

SectionSpec identify_section() {
  const IdentifyTable t;
  SectionSpec s{"identify",
                "Levenberg–Marquardt and its stopping criteria (docs/theory.md §3, paper eqs. 2 and 3).",
                false,
                {},
                {}};
  add_keys(s, t.lm);
  add_keys(s, t.objective);
  add_keys(s, t);
  return s;
}

// Runs an engine's check of its options: the error names the config key, `origin` places it there.
template <class F>
void check_at(const Origin& origin, F&& check) {
  try {
    check();
  } catch (const InputError& e) {
    if (!origin.owns(e)) throw;
    origin.rethrow(e);
  }
}

std::vector<ident::Parameter> build_parameters(const IdentificationSpec& spec, const fem::Law& law) {
  if (spec.parameter.empty())
    spec.origin.fail("parameter", "the project identifies nothing", "no [[parameter]]",
                     "one [[parameter]] per coefficient");
  const std::vector<std::string> names = law.coefficient_names();
  const Eigen::VectorXd c = law.coefficients();
  std::vector<ident::Parameter> out;
  std::vector<ident::Parameter> scales;  // after the law's coefficients (ident::Objective)
  for (const ParameterSpec& p : spec.parameter) {
    const std::string& name = p.name;
    const auto it = std::find(names.begin(), names.end(), name);
    const bool is_scale = it == names.end() && spec.find_test(ident::force_scale_test(name));
    if (it == names.end() && !is_scale) {
      const std::string hint = io::closest_name(name, names);
      std::string all;
      for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
      p.origin.fail("name",
                    fmt::format("not a coefficient of the {} law in [law]{}", law.name(),
                                hint.empty() ? "" : "; did you mean '" + hint + "'?"),
                    "\"" + name + "\"", all + ", or <test>." + ident::kForceScale + " of a [[test]]");
    }
    for (const auto* list : {&out, &scales})
      for (const auto& q : *list)
        if (q.name == name)
          p.origin.fail("name", "this coefficient is identified twice", "\"" + name + "\"", "unique names");
    ident::Parameter x;
    x.name = name;
    x.start = p.start ? *p.start : is_scale ? 1.0 : c(it - names.begin());
    x.scale = p.scale;
    // A start taken from [law] was checked with the law (its constructor); a given one is checked here.
    if (p.start) check_key(p.origin, parameter_section(), "start", *p.start);
    check_key(p.origin, parameter_section(), "scale", p.scale);
    if (x.start == 0 && x.scale == 0)
      p.origin.fail(
          "scale", fmt::format("parameter {} starts at 0 and has no scale: LM's steps are relative to the start", name),
          "0.0", "> 0, the size of a typical change of " + name);
    const io::Reals& b = p.bounds;
    check_key(p.origin, parameter_section(), "bounds", b);
    if (!b.empty()) {
      if (b.size() != 2) p.origin.fail("bounds", "two values: [lower, upper]", io::to_toml(b), "[] or [lower, upper]");
      if (!(b[0] < b[1])) p.origin.fail("bounds", "lower must be below upper", io::to_toml(b), "lower < upper");
      if (x.start < b[0] || x.start > b[1])
        p.origin.fail(p.start ? "start" : "bounds", fmt::format("the start of {} is outside its bounds", name),
                      io::to_toml(x.start), io::to_toml(b));
      x.lower = b[0];
      x.upper = b[1];
    }
    (is_scale ? scales : out).push_back(x);
  }
  out.insert(out.end(), scales.begin(), scales.end());
  return out;
}

// The model of a project without its data: the one check of a spec (validate()) and the first half
// of build_project, so that a build checks each value once.
struct Model {
  std::unique_ptr<fem::Law> law;
  fem::SolveOptions solver;
  std::vector<fem::TestModel> models;
  std::vector<fem::TestModel> coarse_models;  ///< [identify] coarse_mesh; empty without
  std::vector<std::string> names;
  std::vector<ident::Parameter> parameters;
  ident::IdentifyOptions options;
  ident::FieldKind field_kind = ident::FieldKind::cumulative;
  ident::StrainDomain practical;
};

Model check_model(const IdentificationSpec& spec) {
  Model m;
  spec.check_tests();
  m.law = spec.law.law(spec.mesh.region_names());
  m.solver = spec.solver.options();
  for (const auto& t : spec.test) {
    if (t.test_kind() == TestKind::simple_shear)
      t.origin.fail("kind", "identify needs FE tests", "\"simple_shear\"", "uniaxial, biaxial, homogeneous or rig");
    m.models.push_back(t.model(spec.mesh, spec.rig));
    m.names.push_back(t.name);
  }
  m.parameters = build_parameters(spec, *m.law);
  m.options = spec.identify.options();
  check_at(spec.identifiability_origin, [&] { spec.identifiability.validate(); });
  if (spec.stability) check_at(spec.stability_origin, [&] { spec.stability->validate(); });
  if (const io::Reals& c = spec.identify.coarse_mesh; !c.empty()) {  // identify by mesh levels
    const Origin& at = spec.identify.origin;
    check_key(at, identify_section(), "coarse_mesh", c);
    if (c.size() != 2 || c[0] != std::floor(c[0]) || c[1] != std::floor(c[1]))
      at.fail("coarse_mesh", "two whole numbers of elements", io::to_toml(c), "[nx, ny], e.g. [12, 10]");
    MeshSpec mesh = spec.mesh;
    mesh.nx = static_cast<int>(c[0]), mesh.ny = static_cast<int>(c[1]);
    for (std::size_t k = 0; k < spec.test.size(); ++k) {
      TestSpec t = spec.test[k];
      t.mesh.nx = t.mesh.ny = 0;  // the coarse level's nx, ny for every test
      m.coarse_models.push_back(t.model(mesh, spec.rig));
      if (m.coarse_models.back().mesh.dofs() >= m.models[k].mesh.dofs())
        at.fail("coarse_mesh",
                fmt::format("not coarser than the mesh of test '{}' ({} dofs against its {})", spec.test[k].name,
                            m.coarse_models.back().mesh.dofs(), m.models[k].mesh.dofs()),
                io::to_toml(c), "fewer elements than [mesh] and every test's own mesh");
    }
  }
  const ProjectExperimentSpec& ex = spec.experiment;
  m.field_kind = ex.kind();
  const SectionSpec experiment = experiment_section(), data = data_section();
  check_key(ex.origin, experiment, "sigma_edge_displacement", ex.sigma_edge_displacement);
  check_key(ex.origin, experiment, "sigma_edge_force", ex.sigma_edge_force);
  check_key(ex.origin, experiment, "sigma_field", ex.sigma_field);
  const DataSpec& d = spec.data;
  check_key(d.origin, data, "edge_displacement", d.edge_displacement);
  check_key(d.origin, data, "edge_force", d.edge_force);
  check_key(d.origin, data, "field", d.field);
  check_key(d.origin, data, "field_sigma", d.field_sigma);
  if (spec.design) {
    const SectionSpec table = design_section();
    check_key(spec.design->origin, table, "transverse_strains", spec.design->transverse_strains);
    check_key(spec.design->origin, table, "criterion", spec.design->criterion);
    if (spec.design->transverse_strains.empty())
      spec.design->origin.fail("transverse_strains", "no candidate", "[]", "at least one held strain");
  }
  m.practical = spec.eq9.practical();
  (void)d.domain();
  return m;
}

}  // namespace

IdentifyTable IdentifyTable::from_config(const io::Node& s) {
  IdentifyTable t;
  read_keys(s, t.lm);
  read_keys(s, t.objective);
  read_keys(s, t);
  t.origin = Origin(s);
  return t;
}

ident::IdentifyOptions IdentifyTable::options() const {
  check_at(origin, [&] { lm.validate(); });
  return lm;
}

SectionSpec eq9_section() {
  const ident::StrainDomain d;
  SectionSpec s{"eq9",
                "Eq. (9) in result.json (docs/theory.md §9, paper Table 5): the mean relative distance between the\n"
                "identified and the measured force per unit width at the experimental points (each step of a\n"
                "test pulled along wale, material_angle 0, or course, 90: grip force / full width against the\n"
                "centre strain of the measured field), over all points and over the practical domain.",
                false,
                {},
                {}};
  s.keys = {
      key("practical_course", io::Reals{d.eC_min, d.eC_max},
          "[min, max] Green–Lagrange εC of practical use (paper: 60–100 %).", -1, 100),
      key("practical_wale", io::Reals{d.eW_min, d.eW_max},
          "[min, max] Green–Lagrange εW of practical use (paper: 20–40 %).", -1, 100),
      key("nearest", std::int64_t{6},
          "Field points nearest the centre that the centre strain is fitted on (affine), ≥ 3.", 3, 1000000),
      key("min_held_levels", std::int64_t{Eq9Spec{}.min_held_levels},
          "Transverse levels a surface's points must probe it at for eq. 9 to be computed, ≥ 1: the tests'\n"
          "centre strains across the pull at their first step, 0.05 apart. One level is one path through\n"
          "(εC, εW) (uniaxial tests and their repeats): eq. 9 would be a curve's error, so result.json and\n"
          "the report say \"not computed\" with the counts. 1 computes it anyway.",
          1, 1000000),
  };
  return s;
}

SectionSpec identifiability_section() {
  SectionSpec s{
      "identifiability",
      "result.json's \"identifiability\" (docs/theory.md §8, beyond the paper): relative standard errors, the\n"
      "least identifiable direction and each test's share of the information, from ∂r/∂J at the answer.",
      false,
      {},
      {}};
  add_keys(s, ident::IdentifiabilityOptions{});
  return s;
}

SectionSpec stability_section() {
  SectionSpec s{
      "stability",
      "A material-stability barrier for a response surface (docs/theory/fabric.md §3.2): rows that\n"
      "penalise det ∂(F_C, F_W)/∂(εC, εW) < det_margin and own slopes < slope_margin over the strains the\n"
      "rig's fields reach, and a taut law's loss of strong ellipticity (acoustic_margin), so LM's trial laws\n"
      "stay away from the instability where the FE inverts.",
      false,
      {},
      {}};
  // enabled is no option of the barrier: it says whether there is one (IdentificationSpec::stability).
  s.keys = {key("enabled", true,
                "Append the barrier to the objective. On by default for a response surface (issue 29: real data\n"
                "need it); another law takes it only when asked, which is an error.")};
  add_keys(s, ident::StabilityBarrierOptions{});
  return s;
}

io::SectionSpec identify_schema() {
  io::SectionSpec root = case_schema();
  root.help =
      "tricot identify: a project file. The case (specimen, law, solver, tests) models the experiment;\n"
      "LM fits the [[parameter]] coefficients of [law] to the data of [experiment] (docs/theory.md §1–§3).\n"
      "Units: mm, N, N/mm, degrees.";
  root.sections.push_back(experiment_section());
  root.sections.push_back(parameter_section());
  root.sections.push_back(data_section());
  root.sections.push_back(identify_section());
  root.sections.push_back(eq9_section());
  root.sections.push_back(design_section());
  root.sections.push_back(identifiability_section());
  root.sections.push_back(stability_section());
  return root;
}

namespace {

// [eq9]: a practical domain the user gave must meet the data; the default one may not (then
// "practical" is null): an error located at its key, naming the data's strain range.
void check_eq9(const Eq9Spec& eq9, const Project& P) {
  if (!eq9.practical_course && !eq9.practical_wale) return;
  const SurfacePoints& points = P.eq9_points;
  for (int f = 0; f < 2; ++f) {
    if (points[f].empty()) continue;
    try {
      (void)ident::eq9_error(
          points[f], [](double, double) { return 0.0; }, P.eq9_practical);
    } catch (const InputError& e) {
      if (e.where().key != "eq9.practical") throw;
      const std::string what = std::string(e.what()).substr(e.where().key.size() + 2);
      eq9.origin.fail(f == 0 ? "practical_course" : "practical_wale",
                      std::string(f == 0 ? "course" : "wale") + " surface: " + what);
    }
  }
}

// Issue 14: the project and the data must describe the same tests. A [[test]] whose loads differ from
// its forces.csv, or whose control contradicts the truth.json of a synthetic experiment, is named in
// the project file, with the first differing value.
void check_tests_match_data(const CaseSpec& spec, const std::vector<fem::TestModel>& models,
                            const ident::Experiment& experiment, const std::optional<Truth>& truth,
                            const fs::path& dir) {
  for (std::size_t i = 0; i < spec.test.size() && i < models.size(); ++i) {
    const TestSpec& t = spec.test[i];
    const ident::TestData* d = experiment.find(t.name);
    if (!d) continue;
    const std::string forces = (dir / t.name / kForcesFile).string();
    if (truth)
      if (const Truth::Test* tt = truth->find(t.name); tt && !tt->control.empty() && tt->control != t.control)
        t.origin.fail("control",
                      fmt::format("contradicts {}, whose data were made under {} control", (dir / kTruthFile).string(),
                                  tt->control),
                      "\"" + t.control + "\"", "\"" + tt->control + "\"");
    const std::vector<double>& m = models[i].loads;
    const std::vector<double>& L = d->loads;
    if (m.empty() || L.empty()) continue;
    const double tol = 1e-9 * std::max(std::abs(L.back()), std::abs(m.back()));
    std::size_t k = 0;
    while (k < m.size() && k < L.size() && std::abs(m[k] - L[k]) <= tol) ++k;
    if (k == m.size() && k == L.size()) continue;
    const std::string key = !t.loads.empty() ? "loads" : m.size() != L.size() ? "steps" : "load_max";
    const auto at = [](const std::vector<double>& v, std::size_t j) {
      return j < v.size() ? format_number(v[j]) : std::string("none");
    };
    t.origin.fail(key, fmt::format("the test's loads differ from {} from step {} on", forces, k + 1),
                  fmt::format("{} steps, load {} at step {}", m.size(), at(m, k), k + 1),
                  fmt::format("{} steps, load {} at step {} as in the data", L.size(), at(L, k), k + 1));
  }
}

// [[test]] fit_steps: the FE models and the data of the chosen steps alone (a condition's series and a
// guide per step are cut with them).
void select_fit_steps(const IdentificationSpec& spec, ident::FieldKind kind, Project& P,
                      ident::Experiment& experiment) {
  for (std::size_t i = 0; i < spec.test.size() && i < P.models.size(); ++i) {
    const TestSpec& t = spec.test[i];
    if (t.fit_steps.empty()) continue;
    ident::TestData* d = nullptr;
    for (ident::TestData& x : experiment.tests)
      if (x.name == t.name) d = &x;
    if (!d) continue;
    std::vector<int> keep;
    for (double s : t.fit_steps) {
      if (s != std::floor(s) || s > d->steps() || (!keep.empty() && s - 1 <= keep.back()))
        t.origin.fail("fit_steps", fmt::format("not an increasing list of step numbers from 1 to {}", d->steps()),
                      format_number(s),
                      fmt::format("whole numbers, increasing, at most {} (the rows of {})", d->steps(),
                                  (fs::path(spec.experiment.dir) / t.name / kForcesFile).string()));
      keep.push_back(static_cast<int>(s) - 1);
    }
    if (kind == ident::FieldKind::incremental && d->has_field())
      t.origin.fail("fit_steps", "incremental field data refer to the step before: choose steps with cumulative data",
                    "a choice of steps", "[experiment] field_kind = \"cumulative\", or every step");
    *d = d->select_steps(keep);
    auto cut = [&](std::vector<double>& v, std::size_t n) {
      if (v.size() != n) return;
      std::vector<double> out;
      for (int k : keep) out.push_back(v[static_cast<std::size_t>(k)]);
      v = std::move(out);
    };
    for (std::vector<fem::TestModel>* models : {&P.models, &P.coarse_models}) {
      if (i >= models->size()) continue;
      fem::TestModel& m = (*models)[i];
      const std::size_t n = m.loads.size();
      for (fem::BoundaryCondition& c : m.conditions) cut(c.values, n);
      cut(m.guide, n);
      cut(m.loads, n);
    }
  }
}

}  // namespace

SurfacePoints eq9_points(const std::vector<fem::TestModel>& models, const ident::Experiment& experiment, int nearest) {
  SurfacePoints out;
  const auto& tests = experiment.tests;
  for (std::size_t t = 0; t < tests.size() && t < models.size(); ++t) {
    const auto p = ident::test_surface_points(models[t], tests[t], nearest);
    if (!p) continue;
    auto& dst = out[p->force == ident::SurfaceForce::course ? 0 : 1];
    dst.insert(dst.end(), p->points.begin(), p->points.end());
  }
  return out;
}

ProjectExperimentSpec ProjectExperimentSpec::from_config(const io::Node& n) {
  ProjectExperimentSpec e;
  e.dir = n.string("dir");
  e.field_kind = n.string("field_kind");
  e.sigma_edge_displacement = n.real("sigma_edge_displacement");
  e.sigma_edge_force = n.real("sigma_edge_force");
  e.sigma_field = n.real("sigma_field");
  e.sigma_from_truth = n.boolean("sigma_from_truth");
  e.origin = Origin(n);
  return e;
}

ident::FieldKind ProjectExperimentSpec::kind() const {
  check_key(origin, experiment_section(), "field_kind", field_kind);
  return field_kind == "incremental" ? ident::FieldKind::incremental : ident::FieldKind::cumulative;
}

ParameterSpec ParameterSpec::from_config(const io::Node& n) {
  ParameterSpec p;
  p.name = n.string("name");
  if (n.given("start")) p.start = n.real("start");
  p.scale = n.real("scale");
  p.bounds = n.reals("bounds");
  p.origin = Origin(n);
  return p;
}

DataSpec DataSpec::from_config(const io::Node& n) {
  DataSpec d;
  d.edge_displacement = n.real("edge_displacement");
  d.edge_force = n.real("edge_force");
  d.field = n.real("field");
  d.field_uv = n.boolean("field_uv");
  d.field_sigma = n.string("field_sigma");
  d.weighting = n.string("weighting");
  if (n.given("domain_course")) d.domain_course = n.reals("domain_course");
  if (n.given("domain_wale")) d.domain_wale = n.reals("domain_wale");
  d.domain_weight = n.real("domain_weight");
  d.origin = Origin(n);
  if (d.weighting == "fixed" && d.field_sigma == "per_point")
    d.origin.fail("field_sigma", "a σ per point scales the field data, fixed weights do not", "\"per_point\"",
                  "\"group\", or weighting = \"scaled\"");
  if (d.domain_weight > 0 && !d.domain_course && !d.domain_wale)
    d.origin.fail("domain_weight", "weights the steps outside a domain, but no domain is given",
                  format_number(d.domain_weight), "domain_course or domain_wale set, or domain_weight = 0");
  return d;
}

namespace {

// A [min, max] strain interval given at `key` ([data] domain_*, [eq9] practical_*): checked, then set.
void set_interval(const Origin& origin, const SectionSpec& table, const char* key,
                  const std::optional<io::Reals>& given, double& lo, double& hi) {
  if (!given) return;
  const io::Reals& r = *given;
  if (r.size() != 2 || r[0] > r[1])
    origin.fail(key, "not a strain interval", fmt::format("{} values", r.size()), "[min, max] with min <= max");
  check_key(origin, table, key, r);
  lo = r[0], hi = r[1];
}

}  // namespace

std::optional<ident::StrainDomain> DataSpec::domain() const {
  if (!domain_course && !domain_wale) return std::nullopt;
  ident::StrainDomain d;
  d.eC_min = d.eW_min = -1e300, d.eC_max = d.eW_max = 1e300;
  const SectionSpec table = data_section();
  set_interval(origin, table, "domain_course", domain_course, d.eC_min, d.eC_max);
  set_interval(origin, table, "domain_wale", domain_wale, d.eW_min, d.eW_max);
  return d;
}

Eq9Spec Eq9Spec::from_config(const io::Node& n) {
  Eq9Spec e;
  if (n.given("practical_course")) e.practical_course = n.reals("practical_course");
  if (n.given("practical_wale")) e.practical_wale = n.reals("practical_wale");
  e.nearest = static_cast<int>(n.integer("nearest"));
  e.min_held_levels = static_cast<int>(n.integer("min_held_levels"));
  e.origin = Origin(n);
  return e;
}

ident::StrainDomain Eq9Spec::practical() const {
  ident::StrainDomain d;
  const SectionSpec table = eq9_section();
  set_interval(origin, table, "practical_course", practical_course, d.eC_min, d.eC_max);
  set_interval(origin, table, "practical_wale", practical_wale, d.eW_min, d.eW_max);
  check_key(origin, table, "nearest", std::int64_t{nearest});
  return d;
}

IdentificationSpec read_identification_spec(const io::Node& root) {
  IdentificationSpec s;
  static_cast<CaseSpec&>(s) = CaseSpec::from_config(root);
  s.experiment = ProjectExperimentSpec::from_config(root.section("experiment"));
  for (const Node& p : root.array("parameter")) s.parameter.push_back(ParameterSpec::from_config(p));
  s.data = DataSpec::from_config(root.section("data"));
  s.identify = IdentifyTable::from_config(root.section("identify"));
  s.eq9 = Eq9Spec::from_config(root.section("eq9"));
  const Node& id = root.section("identifiability");
  read_keys(id, s.identifiability);
  s.identifiability_origin = Origin(id);
  const Node& st = root.section("stability");
  if (st.boolean("enabled") && (st.given("enabled") || s.law.type == "response_surface"))
    read_keys(st, s.stability.emplace());
  s.stability_origin = Origin(st);
  if (const Node& d = root.section("design"); d.given("transverse_strains")) {
    DesignSpec ds;
    ds.transverse_strains = d.reals("transverse_strains");
    ds.criterion = d.string("criterion");
    ds.origin = Origin(d);
    s.design = ds;
  }
  s.file = root.file();
  return s;
}

void IdentificationSpec::validate() const { (void)check_model(*this); }

Project build_project(const io::Node& root, const fs::path& base) {
  return build_project(read_identification_spec(root), base);
}

void read_loads_from_experiment(IdentificationSpec& spec, const fs::path& base) {
  for (TestSpec& t : spec.test) {
    const TestKind k = t.test_kind();
    if (!t.loads.empty() || t.uniform_loads_given || k == TestKind::rig || k == TestKind::simple_shear) continue;
    const fs::path dir = base / spec.experiment.dir;
    if (!fs::exists(dir / t.name / kForcesFile)) continue;
    t.loads = read_test_data(dir, t.name, ident::FieldKind::cumulative).loads;
  }
}

Project build_project(const IdentificationSpec& given, const fs::path& base) {
  IdentificationSpec spec = given;
  read_loads_from_experiment(spec, base);
  Model m = check_model(spec);
  Project P;
  P.law = std::move(m.law);
  P.solver = m.solver;
  P.models = std::move(m.models);
  P.coarse_models = std::move(m.coarse_models);
  P.options = m.options;
  P.eq9_practical = m.practical;
  P.eq9_nearest = spec.eq9.nearest;
  P.eq9_min_held_levels = spec.eq9.min_held_levels;

  // The experiment.
  const ProjectExperimentSpec& ex = spec.experiment;
  const fs::path dir = base / ex.dir;
  if (!fs::is_directory(dir))
    throw FileError(ex.origin.where("dir"), "experiment folder not found", "\"" + dir.string() + "\"",
                    "a folder written by tricot synth, relative to the project file");
  const auto kind = m.field_kind;
  ident::Experiment experiment = read_experiment(dir, m.names, kind);
  P.truth = read_truth(dir);
  check_tests_match_data(spec, P.models, experiment, P.truth, dir);
  select_fit_steps(spec, kind, P, experiment);
  const bool has_field = std::any_of(experiment.tests.begin(), experiment.tests.end(),
                                     [](const ident::TestData& d) { return d.has_field(); });
  if (P.truth && has_field && P.truth->field_kind != kind)
    ex.origin.fail(
        "field_kind",
        fmt::format("{}/truth.json says the field data are {}", dir.string(), ident::to_string(P.truth->field_kind)),
        "\"" + ex.field_kind + "\"", ident::to_string(P.truth->field_kind));
  for (auto& d : experiment.tests) {
    if (ex.sigma_from_truth) {
      if (!P.truth)
        throw FileError(ex.origin.where("sigma_from_truth"), "the experiment has no truth.json to take σ from",
                        (dir / kTruthFile).string());
      const Truth::Test* t = P.truth->find(d.name);
      if (!t) ex.origin.fail("sigma_from_truth", "truth.json has no test '" + d.name + "'");
      d.sigma = t->sigma;
    } else {
      d.sigma = {ex.sigma_edge_displacement, ex.sigma_edge_force, ex.sigma_field};
    }
  }

  const DataSpec& dn = spec.data;
  for (auto& d : experiment.tests)
    if (dn.field_sigma != "per_point") {
      d.sigma_u.resize(0, 0), d.sigma_v.resize(0, 0);
    } else if (d.has_field() && d.sigma_u.size() == 0) {
      dn.origin.fail("field_sigma", "field.csv of test '" + d.name + "' has no sigma_u, sigma_v columns",
                     "\"per_point\"", "a field.csv written by tricot experiment");
    }
  P.eq9_points = eq9_points(P.models, experiment, P.eq9_nearest);
  if (const auto domain = dn.domain()) {
    ident::Restriction r, coarse;
    try {
      r = ident::restrict_to_domain(P.models, experiment, *domain, P.eq9_nearest);
      if (!P.coarse_models.empty())
        coarse = ident::restrict_to_domain(P.coarse_models, experiment, *domain, P.eq9_nearest);
    } catch (const InputError& e) {
      throw InputError(dn.origin.where(dn.domain_course ? "domain_course" : "domain_wale"), problem_of(e));
    }
    if (dn.domain_weight > 0) {  // weighted: every step kept, those outside the domain weigh less
      for (std::size_t t = 0; t < experiment.tests.size(); ++t) {
        ident::TestData& d = experiment.tests[t];
        d.step_weight.assign(d.steps(), dn.domain_weight);
        std::fill_n(d.step_weight.begin(), r.tests[t].kept, 1.0);
      }
    } else {
      P.models = std::move(r.models);
      P.coarse_models = std::move(coarse.models);
      experiment = std::move(r.experiment);
    }
    P.restriction = std::move(r.tests);
  }
  ident::ObjectiveOptions oo = spec.identify.objective;
  oo.weights.edge_displacement = dn.edge_displacement;
  oo.weights.edge_force = dn.edge_force;
  oo.weights.field = dn.field;
  oo.weights.field_uv = dn.field_uv;
  oo.weights.fixed = dn.weighting == "fixed";
  oo.solver = P.solver;
  oo.threads = P.options.threads;
  // With bounds LM's line search makes trials whose Jacobian it never uses: sensitivities afterwards.
  oo.sensitivities_after = std::any_of(m.parameters.begin(), m.parameters.end(), [](const ident::Parameter& p) {
    return std::isfinite(p.lower) || std::isfinite(p.upper);
  });
  P.objective_options = oo;
  try {
    P.objective = std::make_unique<ident::Objective>(P.models, experiment, *P.law, m.parameters, oo);
    if (!P.coarse_models.empty())
      P.coarse_objective = std::make_unique<ident::Objective>(P.coarse_models, experiment, *P.law, m.parameters, oo);
  } catch (const InputError& e) {
    if (!e.where().file.empty()) throw;
    const std::string& k = e.where().key;
    if (k == "data") throw InputError(dn.origin.where(""), problem_of(e));
    throw InputError({spec.file.string(), 0, k}, std::string(e.what()).substr(k.empty() ? 0 : k.size() + 2));
  }
  P.identifiability = spec.identifiability;
  check_eq9(spec.eq9, P);
  if (spec.stability) {
    try {
      P.stability = std::make_unique<ident::StabilizedObjective>(*P.objective, *spec.stability);
      if (P.coarse_objective)
        P.coarse_stability = std::make_unique<ident::StabilizedObjective>(*P.coarse_objective, *spec.stability);
    } catch (const InputError& e) {  // law.type: the options were checked with the spec
      throw InputError({spec.file.string(), 0, e.where().key}, problem_of(e));
    }
  }
  return P;
}

}  // namespace tricot::project
