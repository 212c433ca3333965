// tricot identify PROJECT.toml -o DIR [--resume]: Levenberg–Marquardt identification of a law's
// coefficients from an experiment (THEORY §1–§3, §7, §8; paper §2). Writes DIR/result.json,
// DIR/history.csv, DIR/checkpoint.json (after every accepted step) and DIR/plots/*.png.
#include "identify.hpp"

#include <fmt/format.h>

#include <csignal>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "case_config.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/objective.hpp"
#include "tricot/io/files.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

namespace fs = std::filesystem;
using io::KeySpec;
using io::Node;
using io::SectionSpec;
using json = nlohmann::ordered_json;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr const char* kCheckpointFile = "checkpoint.json";

using io::key;

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

// FNV-1a over bytes: the checkpoint's fingerprint of the data and the model it belongs to.
struct Fingerprint {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  void add(const Eigen::VectorXd& v) { add(v.data(), sizeof(double) * static_cast<std::size_t>(v.size())); }
  void add(const std::string& s) { add(s.data(), s.size()); }
  std::string hex() const { return fmt::format("{:016x}", h); }
};

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

ident::IdentifyOptions build_options(const Node& s) {
  ident::IdentifyOptions o;
  o.epsilon = s.real("epsilon");
  o.delta = s.real("delta");
  o.function_tolerance = s.real("function_tolerance");
  o.gradient_tolerance = s.real("gradient_tolerance");
  o.max_iterations = static_cast<int>(s.integer("max_iterations"));
  o.stability_test = s.boolean("stability_test");
  o.stability_eta = s.real("stability_eta");
  o.max_restarts = static_cast<int>(s.integer("max_restarts"));
  o.jacobian = s.string("jacobian") == "exact" ? ident::JacobianMode::exact : ident::JacobianMode::finite_difference;
  o.difference = s.string("difference") == "central" ? ident::Difference::central : ident::Difference::forward;
  o.fd_step = s.real("fd_step");
  o.threads = static_cast<int>(s.integer("threads"));
  o.initial_trust_region_radius = s.real("initial_trust_region_radius");
  try {
    o.validate();
  } catch (const InputError& e) {
    std::string k = e.where().key;
    if (k.rfind("identify.", 0) == 0) k = k.substr(9);
    if (k == "step") k = "fd_step";
    if (k == "mode") k = "jacobian";
    relocate(e, s, k);
  }
  return o;
}

// ---------------------------------------------------------------------------------------------------
// Checkpoint (DIR/checkpoint.json): the library's Checkpoint plus the fingerprint.

json vec_json(const Eigen::VectorXd& v) { return json(std::vector<double>(v.data(), v.data() + v.size())); }

Eigen::VectorXd json_vec(const json& j) {
  const auto v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

void write_checkpoint(const fs::path& file, const ident::Checkpoint& c, const std::string& fingerprint) {
  json j;
  j["fingerprint"] = fingerprint;
  j["names"] = c.names;
  j["scales"] = vec_json(c.scales);
  j["x"] = vec_json(c.x);
  j["parameters"] = vec_json(c.parameters);
  j["objective"] = c.objective;
  j["trust_region_radius"] = c.trust_region_radius;
  j["iterations"] = c.iterations;
  j["evaluations"] = c.evaluations;
  j["jacobian_evaluations"] = c.jacobian_evaluations;
  j["failed_evaluations"] = c.failed_evaluations;
  j["restarts"] = c.restarts;
  j["wall_seconds"] = c.wall_seconds;
  json h = json::array();
  for (const auto& e : c.history)
    h.push_back({{"iteration", e.iteration}, {"objective", e.objective}, {"parameters", vec_json(e.parameters)},
                 {"restart", e.restart}});
  j["history"] = h;
  io::write_atomic(file, j.dump(1) + "\n");
}

ident::Checkpoint read_checkpoint(const fs::path& file, const std::string& fingerprint) {
  if (!fs::exists(file))
    throw FileError({file.string(), 0, ""}, "nothing to resume: no checkpoint in the output folder", "",
                    "the -o folder of an earlier run of this project");
  ident::Checkpoint c;
  try {
    const json j = json::parse(io::read_text(file));
    if (j.at("fingerprint").get<std::string>() != fingerprint)
      throw InputError({file.string(), 0, "fingerprint"},
                       "the checkpoint belongs to other data or another model (the experiment, [law], [mesh], "
                       "[[test]], [[parameter]] or [data] changed); run without --resume to start afresh");
    c.names = j.at("names").get<std::vector<std::string>>();
    c.scales = json_vec(j.at("scales"));
    c.x = json_vec(j.at("x"));
    c.parameters = json_vec(j.at("parameters"));
    c.objective = j.at("objective").get<double>();
    c.trust_region_radius = j.at("trust_region_radius").get<double>();
    c.iterations = j.at("iterations").get<int>();
    c.evaluations = j.at("evaluations").get<int>();
    c.jacobian_evaluations = j.at("jacobian_evaluations").get<int>();
    c.failed_evaluations = j.at("failed_evaluations").get<int>();
    c.restarts = j.at("restarts").get<int>();
    c.wall_seconds = j.at("wall_seconds").get<double>();
    for (const json& e : j.at("history"))
      c.history.push_back({e.at("iteration").get<int>(), e.at("objective").get<double>(), json_vec(e.at("parameters")),
                           e.at("restart").get<int>()});
  } catch (const json::exception& e) {
    throw InputError({file.string(), 0, ""}, std::string("not a tricot checkpoint: ") + e.what());
  }
  return c;
}

// ---------------------------------------------------------------------------------------------------
// Outputs

json named(const std::vector<std::string>& names, const Eigen::VectorXd& v) {
  json j = json::object();
  for (std::size_t k = 0; k < names.size() && Eigen::Index(k) < v.size(); ++k) j[names[k]] = v(Eigen::Index(k));
  return j;
}

json result_json(const IdentifyOutcome& o, const ident::Objective& objective, bool resumed) {
  const ident::IdentifyResult& r = o.result;
  const ident::Uncertainty& u = r.uncertainty;
  json j;
  j["parameters"] = named(r.names, r.parameters);
  j["std_error"] = named(r.names, u.std_error);  // inf (unidentifiable) is written as null
  json corr = json::array();
  for (Eigen::Index i = 0; i < u.correlation.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index k = 0; k < u.correlation.cols(); ++k) row.push_back(u.correlation(i, k));
    corr.push_back(row);
  }
  j["correlation"] = corr;
  j["objective"] = r.objective;
  j["iterations"] = r.iterations;
  j["evaluations"] = r.evaluations;
  j["termination"] = ident::to_string(r.termination);
  j["message"] = r.message;
  j["wall_seconds"] = r.wall_seconds;
  j["jacobian"] = ident::to_string(r.jacobian);
  // Beyond DESIGN.md's keys.
  j["names"] = r.names;
  j["converged"] = r.converged();
  j["stability_passed"] = r.stability_passed;
  j["restarts"] = r.restarts;
  j["failed_evaluations"] = r.failed_evaluations;
  j["jacobian_evaluations"] = r.jacobian_evaluations;
  j["resumed"] = resumed;
  j["start"] = named(r.names, r.start);
  j["condition_number"] = u.condition_number;
  j["least_identifiable"] = named(r.names, u.least_identifiable);
  j["singular_values"] = vec_json(u.singular_values);
  j["covariance_from"] = u.from_sigma ? "measurement_sigma" : "fit";
  j["sigma2"] = u.sigma2;
  j["residuals"] = o.residuals;
  json groups = json::array();
  for (const auto& g : objective.data().groups())
    groups.push_back({{"name", g.name}, {"size", g.size}, {"weight", g.weight}, {"scale", g.scale}, {"sigma", g.sigma}});
  j["data"] = groups;
  if (o.truth) {
    json truth = json::object(), err = json::object(), in_se = json::object();
    for (std::size_t k = 0; k < r.names.size(); ++k) {
      const auto t = o.truth->value(r.names[k]);
      if (!t) continue;
      truth[r.names[k]] = *t;
      err[r.names[k]] = (r.parameters(Eigen::Index(k)) - *t) / std::abs(*t);
      if (Eigen::Index(k) < u.std_error.size())
        in_se[r.names[k]] = std::abs(r.parameters(Eigen::Index(k)) - *t) / u.std_error(Eigen::Index(k));
    }
    j["truth"] = truth;
    j["relative_error"] = err;
    j["error_in_std_errors"] = in_se;
  }
  return j;
}

void write_history(const fs::path& file, const ident::IdentifyResult& r) {
  io::Table t;
  t.columns = {"iteration", "objective"};
  for (const auto& n : r.names) t.columns.push_back(n);
  for (const auto& e : r.history) {
    std::vector<double> row{double(e.iteration), e.objective};
    for (Eigen::Index k = 0; k < e.parameters.size(); ++k) row.push_back(e.parameters(k));
    t.rows.push_back(std::move(row));
  }
  io::write_atomic(file, io::to_csv(t));
}

// Objective (log scale) and every coefficient normalised, against the LM iteration: the paper's
// Figs 7–9. Normalised by the truth when the experiment has one, else by the identified value.
void plot_history(const fs::path& dir, const IdentifyOutcome& o, Console& console) {
  const ident::IdentifyResult& r = o.result;
  if (r.history.empty()) return;
  std::string lines;
  for (std::size_t k = 0; k < r.names.size(); ++k) {
    const auto truth = o.truth ? o.truth->value(r.names[k]) : std::nullopt;
    const double ref = truth && *truth != 0 ? *truth : r.parameters(Eigen::Index(k));
    if (ref == 0) continue;
    lines += fmt::format("{}{} using 1:(${}/({:.17g})) with linespoints pt 7 ps 0.5 title \"{}\"", lines.empty() ? "" : ", \\\n  ",
                         io::gnuplot_quote(dir / "history.csv"), k + 3, ref, r.names[k]);
  }
  const std::string by = o.truth ? "truth" : "identified value";
  const std::string script = fmt::format(R"gp(set terminal pngcairo size 900,800 font ",11"
set output {0}
set datafile separator ","
set multiplot layout 2,1 title "tricot identify: {1} ({2} Jacobian)" noenhanced
set grid
set key top right
set logscale y
set format y "10^{{%L}}"
set ylabel "objective f"
plot {3} using 1:2 skip 1 with linespoints pt 7 ps 0.5 lc rgb "#000000" title "f (eq. 1)"
unset logscale y
set format y "%g"
set xlabel "LM iteration"
set ylabel "coefficient / {4}"
set key bottom right
plot {5}
unset multiplot
)gp",
                                         io::gnuplot_quote(dir / "plots" / "history.png"), o.data,
                                         ident::to_string(r.jacobian), io::gnuplot_quote(dir / "history.csv"), by, lines);
  std::string why;
  if (!io::run_gnuplot(script, &why)) console.print("  (no plot: " + why + ")");
}

// The identified model against the measured edge data, per test: DIR/fit_<test>.csv and plots/fit_<test>.png.
void write_fit(const fs::path& dir, const ident::Objective& objective, const ident::IdentifyResult& r,
               const fem::SolveOptions& solver, bool plots, Console& console) {
  const auto law = objective.law_at(r.parameters);
  for (std::size_t t = 0; t < objective.models().size(); ++t) {
    const fem::TestModel& m = objective.models()[t];
    const ident::TestData& d = objective.experiment().tests[t];
    const fem::SimulationResult sim = fem::simulate(m, *law, solver);
    if (!sim.usable()) continue;
    io::Table tab;
    tab.columns = {"step", "load", "model_edge_displacement", "model_edge_force"};
    if (!d.edge_displacement.empty()) tab.columns.push_back("edge_displacement");
    if (!d.edge_force.empty()) tab.columns.push_back("edge_force");
    for (int k = 0; k < d.steps(); ++k) {
      std::vector<double> row{double(k + 1), d.loads[k], sim.steps[k].edge_displacement, sim.steps[k].edge_force};
      if (!d.edge_displacement.empty()) row.push_back(d.edge_displacement[k]);
      if (!d.edge_force.empty()) row.push_back(d.edge_force[k]);
      tab.rows.push_back(std::move(row));
    }
    const fs::path csv = dir / ("fit_" + m.name + ".csv");
    io::write_atomic(csv, io::to_csv(tab));
    if (!plots || (d.edge_displacement.empty() && d.edge_force.empty())) continue;
    const std::string measured =
        d.edge_displacement.empty() ? "\"model_edge_displacement\":\"edge_force\"" : d.edge_force.empty()
                                                                                         ? "\"edge_displacement\":\"model_edge_force\""
                                                                                         : "\"edge_displacement\":\"edge_force\"";
    std::string why;
    if (!io::run_gnuplot(fmt::format(R"gp(set terminal pngcairo size 800,560 font ",11"
set output {0}
set datafile separator ","
set grid
set key top left
set title "{1}: measured and identified grip response" noenhanced
set xlabel "grip displacement (quarter model), mm"
set ylabel "grip force, N"
plot {2} using {3} with points pt 6 ps 1 title "measured", \
  {2} using "model_edge_displacement":"model_edge_force" with lines lw 2 title "identified model"
)gp",
                                     io::gnuplot_quote(dir / "plots" / ("fit_" + m.name + ".png")), m.name,
                                     io::gnuplot_quote(csv), measured),
                         &why))
      console.print("  (no plot: " + why + ")");
  }
}

void print_summary(const IdentifyOutcome& o, const fs::path& out, Console& console) {
  const ident::IdentifyResult& r = o.result;
  const bool truth = o.truth.has_value();
  console.print(fmt::format("{}: {} after {} LM iterations, {} evaluations, {} ({}), f = {:.4g}",
                            r.converged() ? "converged" : "NOT converged", ident::to_string(r.termination),
                            r.iterations, r.evaluations, format_duration(r.wall_seconds), r.message, r.objective));
  std::string head = fmt::format("  {:<10} {:>13} {:>13} {:>11}", "", "start", "identified", "std error");
  if (truth) head += fmt::format(" {:>13} {:>10} {:>7}", "truth", "rel. error", "in s.e.");
  console.print(head);
  for (std::size_t k = 0; k < r.names.size(); ++k) {
    const Eigen::Index i = Eigen::Index(k);
    const double se = i < r.uncertainty.std_error.size() ? r.uncertainty.std_error(i) : std::nan("");
    std::string line = fmt::format("  {:<10} {:>13.6g} {:>13.6g} {:>11.3g}", r.names[k], r.start(i), r.parameters(i), se);
    if (truth)
      if (const auto t = o.truth->value(r.names[k]))
        line += fmt::format(" {:>13.6g} {:>9.3g}% {:>7.2f}", *t, 100 * (r.parameters(i) - *t) / std::abs(*t),
                            std::abs(r.parameters(i) - *t) / se);
    console.print(line);
  }
  const ident::Uncertainty& u = r.uncertainty;
  if (u.least_identifiable.size() > 0) {
    std::string dir;
    for (std::size_t k = 0; k < r.names.size(); ++k)
      dir += fmt::format("{}{:+.3f}·δ{}", k ? " " : "", u.least_identifiable(Eigen::Index(k)), r.names[k]);
    console.print(fmt::format("  condition number {:.3g}; least identifiable direction (relative): {}",
                              u.condition_number, dir));
  }
  console.print("  -> " + (out / "result.json").string() + ", history.csv, plots/");
}

struct IdentifyArgs {
  std::string project, out_dir;
  bool resume = false, verbose = false, quiet = false, no_plots = false;
  int kill_after = 0;
};

constexpr const char* kFooter = R"(
A project file (TOML) is a case file (see `tricot simulate --help`: [mesh], [law], [solver],
[[test]]) — the model of each test on the identification mesh — plus where the measurements are, which
coefficients to identify, which data to compare, and how LM stops:

  [mesh]                        # the identification mesh (coarser than synth's: no inverse crime)
  width = 50.0
  height = 200.0
  nx = 10
  ny = 34

  [law]                         # the law; its values are the start unless [[parameter]] says
  type = "mooney_rivlin"
  [law.mooney_rivlin]
  terms = ["C10", "C20", "C21", "C03"]
  values = [0.05, -0.0125, 0.0075, 0.005]

  [[test]]                      # one per sub-folder of the experiment, same name and steps
  name = "tension"
  kind = "uniaxial"
  control = "force"
  load_max = 20.0
  steps = 35

  [experiment]
  dir = "experiment"            # relative to this file: tension/forces.csv, tension/field.csv
  field_kind = "cumulative"

  [[parameter]]
  name = "C10"                  # start = the [law] value; or start = 0.05
  [[parameter]]
  name = "C03"
  scale = 0.01                  # needed when the start is 0

  [data]
  edge_displacement = 1.0       # weights; 0 leaves a kind of data out
  field = 1.0

  [identify]
  epsilon = 1e-12               # eq. (2)
  delta = 1e-5                  # eq. (3)
  jacobian = "exact"            # or "finite_difference" (the paper's way)

Outputs in DIR: result.json (parameters, std_error, correlation, objective, iterations, evaluations,
termination, message, wall_seconds, jacobian, and condition_number, least_identifiable, start,
restarts, truth and relative_error for a synthetic experiment), history.csv (iteration, objective,
one column per coefficient), fit_<test>.csv, plots/history.png, plots/fit_<test>.png, and
checkpoint.json, rewritten after every accepted LM step: `--resume` continues a killed run from it
and reaches the same answer.

Examples:
  tricot identify examples/uniaxial-mooney/project.toml -o out/identify
  tricot identify examples/uniaxial-mooney/project.toml -o out/identify --resume

Exit codes: 0 converged, 2 bad command line, project or data, 3 a file or folder missing,
4 ran but did not converge (result.json says why).
)";

}  // namespace

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
  return root;
}

Project build_project(const io::Node& root, const fs::path& base) {
  Project P;
  check_tests(root);
  P.law = build_law(root.section("law"));
  P.solver = build_solver(root.section("solver"));
  std::vector<std::string> names;
  for (const auto& t : root.array("test")) {
    if (test_kind(t) == TestKind::simple_shear)
      t.fail("kind", "identify needs FE tests", "\"simple_shear\"", "uniaxial, biaxial or homogeneous");
    P.models.push_back(build_test(t, root.section("mesh")));
    names.push_back(t.string("name"));
  }
  std::vector<ident::Parameter> parameters = build_parameters(root, *P.law);
  P.options = build_options(root.section("identify"));

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
  return P;
}

IdentifyOutcome run_identification(const io::Node& root, const IdentifyRequest& req, Console& console) {
  Project P = build_project(root, req.base);
  const auto& law = P.law;
  const auto& models = P.models;
  const auto& solver = P.solver;
  auto& options = P.options;
  const auto& objective = P.objective;
  const auto& parameters = objective->parameters();
  IdentifyOutcome outcome;
  outcome.truth = P.truth;
  outcome.residuals = objective->residuals();
  outcome.dofs = models.front().mesh.dofs();
  for (const auto& g : objective->data().groups())
    outcome.data += fmt::format("{}{} ({})", outcome.data.empty() ? "" : ", ", g.name, g.size);

  // Checkpoints belong to these data and this model; [identify] may change between runs.
  Fingerprint fp;
  fp.add(objective->data().measured());
  fp.add(objective->data().factors());
  for (const auto& p : objective->parameters()) {
    fp.add(p.name);
    fp.add(&p.start, sizeof p.start);
    const double s = p.resolved_scale();
    fp.add(&s, sizeof s);
  }
  fp.add(law->coefficients());
  for (const auto& m : models) fp.add(m.mesh.X.reshaped().eval());
  const std::string fingerprint = fp.hex();
  const fs::path checkpoint = req.out / kCheckpointFile;
  if (req.resume) options.resume_from = read_checkpoint(checkpoint, fingerprint);
  fs::create_directories(req.out);
  int checkpoints = 0;
  options.on_checkpoint = [&](const ident::Checkpoint& c) {
    write_checkpoint(checkpoint, c, fingerprint);
    if (req.observe) req.observe(c);
    if (req.kill_after > 0 && ++checkpoints >= req.kill_after) std::raise(SIGKILL);  // testing aid
  };

  console.print(fmt::format("identify: {} coefficients of {} from {} values ({}), {} dofs, {} Jacobian{}",
                            parameters.size(), law->name(), outcome.residuals, outcome.data, outcome.dofs,
                            ident::to_string(options.jacobian),
                            req.resume ? fmt::format(", resumed at iteration {}", options.resume_from->iterations) : ""));
  outcome.result = ident::identify(*objective, options, console.reporter());

  // Outputs.
  io::write_atomic(req.out / "result.json", result_json(outcome, *objective, req.resume).dump(2) + "\n");
  write_history(req.out / "history.csv", outcome.result);
  if (req.plots) fs::create_directories(req.out / "plots");
  if (outcome.result.termination != ident::Termination::fe_failure)
    write_fit(req.out, *objective, outcome.result, solver, req.plots, console);
  if (req.plots) plot_history(req.out, outcome, console);
  if (req.print_summary) print_summary(outcome, req.out, console);
  return outcome;
}

Runner add_identify(CLI::App& app) {
  auto args = std::make_shared<IdentifyArgs>();
  CLI::App* cmd = app.add_subcommand(
      "identify", "Identify the law's coefficients from an experiment (Levenberg–Marquardt on FE models)");
  cmd->footer(kFooter);
  cmd->add_option("project", args->project, "The project file (TOML); see --print-config")->required();
  cmd->add_option("-o,--out", args->out_dir, "Output folder")->required();
  cmd->add_flag("--resume", args->resume, "Continue a killed run from DIR/checkpoint.json");
  cmd->add_flag("--no-plots", args->no_plots, "Do not run gnuplot");
  cmd->add_flag("-v,--verbose", args->verbose, "Log lines of the engines");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress line");
  cmd->add_option("--kill-after", args->kill_after, "Testing aid: kill the run after N checkpoints")->group("");
  add_print_config(cmd, identify_schema);
  return [args]() {
    const io::Node root = io::read_config(identify_schema(), args->project);
    Console console(args->verbose, args->quiet);
    IdentifyRequest req;
    req.base = fs::path(args->project).parent_path();
    req.out = args->out_dir;
    req.resume = args->resume;
    req.plots = !args->no_plots;
    req.kill_after = args->kill_after;
    const IdentifyOutcome o = run_identification(root, req, console);
    return o.result.converged() ? ExitCode::ok : ExitCode::not_converged;
  };
}

}  // namespace tricot::cli
