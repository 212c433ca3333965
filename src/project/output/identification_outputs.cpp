// The outputs of an identification: result.json, history.csv, fit_<test>.csv and the gnuplot plots.
#include "output/identification_outputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <omp.h>

#include "output/json.hpp"
#include "output/plot.hpp"
#include "tricot/core/error.hpp"
#include "tricot/core/format.hpp"
#include "tricot/fem/locate.hpp"
#include "tricot/fem/wrinkling.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/identifiability.hpp"
#include "tricot/ident/synthetic.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

json named(const std::vector<std::string>& names, const Eigen::VectorXd& v) {
  json j = json::object();
  for (std::size_t k = 0; k < names.size() && Eigen::Index(k) < v.size(); ++k) j[names[k]] = v(Eigen::Index(k));
  return j;
}

double chi2_per_dof(const ident::Objective& objective, const ident::IdentifyResult& r) {
  const Eigen::Index dof = objective.data().size() - r.parameters.size();
  return dof > 0 ? objective.data().chi_square(r.residuals) / static_cast<double>(dof) : NAN;
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
  // Beyond docs/design.md's keys.
  j["names"] = r.names;
  j["converged"] = r.converged();
  j["stability_passed"] = r.stability_passed;
  j["restarts"] = r.restarts;
  j["failed_evaluations"] = r.failed_evaluations;
  j["skipped_evaluations"] = r.skipped_evaluations;
  j["jacobian_evaluations"] = r.jacobian_evaluations;
  j["resumed"] = resumed;
  j["start"] = named(r.names, r.start);
  j["ranks"] = o.ranks;             // MPI processes that simulated the tests
  j["threads"] = o.threads;         // OpenMP threads per process for the tests
  j["cpus"] = omp_get_num_procs();  // CPUs this process may run on: its affinity (an MPI rank's binding)
  if (o.levels) {                   // [identify] coarse_mesh: what each level did; the keys above are the last level's
    json levels = json::array();
    for (std::size_t l = 0; l < o.levels->levels.size(); ++l) {
      const ident::IdentifyResult& x = o.levels->levels[l];
      levels.push_back({{"dofs", o.level_dofs[l]},
                        {"iterations", x.iterations},
                        {"evaluations", x.evaluations},
                        {"termination", ident::to_string(x.termination)},
                        {"objective", x.objective},
                        {"wall_seconds", x.wall_seconds},
                        {"parameters", named(r.names, x.parameters)}});
    }
    j["levels"] = levels;
    j["coarse_evaluations"] = o.levels->coarse_evaluations;  // the first level's, inside the corrected models
  }
  j["condition_number"] = u.condition_number;
  j["least_identifiable"] = named(r.names, u.least_identifiable);
  j["singular_values"] = vec_json(u.singular_values);
  j["covariance_from"] = u.from_sigma ? "measurement_sigma" : "fit";
  j["sigma2"] = u.sigma2;
  j["residuals"] = o.residuals;
  // Each group's part of f = ½ Σ r² and its share (issue 29: no group buried by another's scaling), and
  // with measurement σ, χ²/dof: 1 for a fit to the noise, its root the model-error factor (docs/theory.md §8).
  const Eigen::VectorXd& res = r.residuals;
  const bool have_r = res.size() >= objective.data().size();
  const double f_total = have_r ? 0.5 * res.squaredNorm() : 0.0;
  json groups = json::array();
  for (const auto& g : objective.data().groups()) {
    json x = {{"name", g.name}, {"size", g.size}, {"weight", g.weight}, {"scale", g.scale}, {"sigma", g.sigma}};
    const double fg = have_r ? 0.5 * res.segment(g.offset, g.size).squaredNorm() : NAN;
    x["f"] = have_r ? json(fg) : json(nullptr);
    x["share"] = have_r && f_total > 0 ? json(fg / f_total) : json(nullptr);
    groups.push_back(x);
  }
  j["data"] = groups;
  const double chi2 = chi2_per_dof(objective, r);
  j["chi2_per_dof"] = std::isfinite(chi2) ? json(chi2) : json(nullptr);
  j["model_error_factor"] = std::isfinite(chi2) ? json(std::sqrt(chi2)) : json(nullptr);
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

namespace {

// The identified force per unit width at (εC, εW): P of the homogeneous state F = diag(λC, λW) in the
// material frame (Q = I), whose P11 and P22 are the course and wale forces (docs/theory.md §5).
double identified_force(const fem::Law& law, int i, double eC, double eW) {
  fem::LawInput in;
  in.F = Vec2(std::sqrt(1 + 2 * eC), std::sqrt(1 + 2 * eW)).asDiagonal();
  fem::LawOutput out;
  law.evaluate(in, {false, false}, out);
  return out.P(i, i);
}

}  // namespace

json eq9_json(const SurfacePoints& points, const fem::Law& law, const ident::StrainDomain& practical,
              int min_held_levels) {
  auto force = [&](int i) { return [&law, i](double eC, double eW) { return identified_force(law, i, eC, eW); }; };
  json j;
  for (int f = 0; f < 2; ++f) {
    const char* name = f == 0 ? "course" : "wale";
    if (points[f].empty()) {
      j[name] = nullptr;
      continue;
    }
    const int levels = ident::held_levels(points[f]);
    if (levels < min_held_levels) {
      const auto in_practical = std::count_if(points[f].begin(), points[f].end(), [&](const ident::SurfacePoint& p) {
        return practical.contains(p.eC, p.eW);
      });
      j[name] = {{"computed", false},
                 {"whole", nullptr},
                 {"practical", nullptr},
                 {"points_whole", points[f].size()},
                 {"points_practical", in_practical},
                 {"held_levels", levels},
                 {"reason", fmt::format("{} points from {} transverse level{} (eq9.min_held_levels = {}): one path "
                                        "through the strain plane, not the surface",
                                        points[f].size(), levels, levels == 1 ? "" : "s", min_held_levels)}};
      continue;
    }
    ident::Eq9Error e;
    try {
      e = ident::eq9_error(points[f], force(f), practical);
    } catch (const InputError& err) {
      if (err.where().key != "eq9.practical") throw;
      ident::StrainDomain all;  // the default domain holds no point of these data: whole range only
      all.eC_min = all.eW_min = -1e300;
      all.eC_max = all.eW_max = 1e300;
      e = ident::eq9_error(points[f], force(f), all);
      e.practical = std::numeric_limits<double>::quiet_NaN(), e.points_practical = 0;
    }
    j[name] = {{"computed", true},
               {"whole", e.whole},
               {"practical", e.practical},
               {"points_whole", e.points_whole},
               {"points_practical", e.points_practical},
               {"held_levels", levels}};
  }
  j["practical"] = {{"course", {practical.eC_min, practical.eC_max}}, {"wale", {practical.eW_min, practical.eW_max}}};
  return j;
}

void write_eq9(const fs::path& dir, const SurfacePoints& points, const fem::Law& law,
               const ident::StrainDomain& practical, bool plots, const Log& log) {
  for (int f = 0; f < 2; ++f) {
    if (points[f].empty()) continue;
    const std::string name = f == 0 ? "course" : "wale";
    io::Table t;
    t.columns = {"eC", "eW", "force_exp", "force_id", "relative_error", "practical"};
    double c0 = 1e300, c1 = -1e300, w0 = 1e300, w1 = -1e300;
    for (const auto& p : points[f]) {
      const double id = identified_force(law, f, p.eC, p.eW);
      t.rows.push_back({p.eC, p.eW, p.force, id, p.force != 0 ? std::abs(id - p.force) / std::abs(p.force) : 0.0,
                        practical.contains(p.eC, p.eW) ? 1.0 : 0.0});
      c0 = std::min(c0, p.eC), c1 = std::max(c1, p.eC), w0 = std::min(w0, p.eW), w1 = std::max(w1, p.eW);
    }
    io::write_atomic(dir / ("eq9_" + name + ".csv"), io::to_csv(t));
    // The identified surface on a 25 × 25 grid over the points' strain range (blank line per scan).
    io::CsvWriter grid;
    grid.row({"eC", "eW", "force_id"});
    constexpr io::CsvFormat kDigits = io::CsvFormat::significant(9);
    for (int a = 0; a <= 24; ++a) {
      for (int b = 0; b <= 24; ++b) {
        const double eC = c0 + (c1 - c0) * a / 24, eW = w0 + (w1 - w0) * b / 24;
        grid.number(eC, kDigits).number(eW, kDigits).number(identified_force(law, f, eC, eW), kDigits).end_row();
      }
      grid.end_row();
    }
    io::write_atomic(dir / ("eq9_surface_" + name + ".csv"), grid.take());
    if (!plots) continue;
    const std::string body = fmt::format(R"gp(set multiplot layout 1,2 \
  title "eq. 9, {0} force: identified surface and experimental points; relative error (practical domain outlined)" \
  noenhanced
set xlabel "eps_C (Green-Lagrange)"
set ylabel "eps_W"
set zlabel "F_{{{0}}} [N/mm]" rotate
set view 60,35
set key top left
splot {1} using 1:2:3 skip 1 with lines lc rgb "#4060c0" title "identified", \
  {2} using 1:2:3 skip 1 with points pt 7 ps 0.7 lc rgb "#000000" title "experimental"
set view map
unset zlabel
set key off
set title "|F_id - F_exp| / |F_exp|" noenhanced
set object 1 rect from {3:.6g},{4:.6g} to {5:.6g},{6:.6g} fs empty border lc rgb "#d00000" lw 2 front
set cbrange [0:*]
set palette rgbformulae 22,13,-31
plot {2} using 1:2:5 skip 1 with points pt 7 ps 1.2 palette
unset multiplot
)gp",
                                         name, io::gnuplot_quote(dir / ("eq9_surface_" + name + ".csv")),
                                         io::gnuplot_quote(dir / ("eq9_" + name + ".csv")), practical.eC_min,
                                         practical.eW_min, practical.eC_max, practical.eW_max);
    plot({.png = dir / "plots" / ("eq9_" + name + ".png"), .width = 1300, .height = 560}, body, log);
  }
}

json identifiability_json(const ident::Objective& objective, const ident::IdentifyResult& r, const ident::Evaluation& e,
                          ident::IdentifiabilityOptions options) {
  if (!e.ok || e.jacobian.cols() != r.parameters.size()) return nullptr;
  const auto& tests = objective.experiment().tests;
  std::vector<std::vector<int>> rows(tests.size());
  for (const auto& g : objective.data().groups())
    for (int i = 0; i < g.size; ++i) rows[g.test].push_back(g.offset + i);
  Eigen::VectorXd scale(r.parameters.size());
  for (Eigen::Index k = 0; k < scale.size(); ++k) scale(k) = objective.parameters()[k].resolved_scale();
  if (r.uncertainty.sigma2 > 0 && std::isfinite(r.uncertainty.sigma2)) options.sigma2 = r.uncertainty.sigma2;
  const ident::IdentifiabilityReport id = ident::identifiability(e.jacobian, r.parameters, scale, rows, options);
  json pinned = json::object();
  for (std::size_t k = 0; k < r.names.size(); ++k) pinned[r.names[k]] = bool(id.pinned[k]);
  json per_test = json::object();
  for (std::size_t t = 0; t < tests.size(); ++t)
    per_test[tests[t].name] = {{"trace_share", id.trace_share[t]},
                               {"weak_direction_share", id.weak_direction_share[t]}};
  return {{"relative_std_error", named(r.names, id.relative_std_error)},
          {"pinned", pinned},
          {"pinned_relative_error", options.pinned_relative_error},
          {"least_identifiable", named(r.names, id.least_identifiable)},
          {"smallest_eigenvalue", id.smallest_eigenvalue},
          {"largest_eigenvalue", id.largest_eigenvalue},
          {"tests", per_test}};
}

json design_json(const IdentificationSpec& spec, const Project& P, const ident::IdentifyResult& r,
                 const ident::Evaluation& at_answer, const Log& log) {
  if (!spec.design || !at_answer.ok || at_answer.jacobian.cols() != r.parameters.size()) return nullptr;
  const ident::Objective& objective = *P.objective;
  const std::unique_ptr<fem::Law> law = objective.law_at(r.parameters);
  json rows = json::array();
  std::vector<ident::DesignCandidate> candidates;
  std::vector<std::size_t> row_of;  // candidates[i] is rows[row_of[i]]
  for (const char* pull : {"wale", "course"}) {
    // The first rig test of this pull with data in the objective: the template of the candidates.
    const TestSpec* tpl = nullptr;
    const ident::TestData* data = nullptr;
    std::vector<double> held;
    for (const TestSpec& t : spec.test) {
      if (t.test_kind() != TestKind::rig || t.pull != pull) continue;
      held.push_back(t.transverse_strain);
      const ident::TestData* d = objective.experiment().find(t.name);
      if (!tpl && d) tpl = &t, data = d;
    }
    if (!tpl) continue;
    for (double v : spec.design->transverse_strains) {
      if (std::any_of(held.begin(), held.end(), [v](double h) { return std::abs(h - v) < 1e-9; })) continue;
      TestSpec c = *tpl;
      c.name = fmt::format("{}-held-{}", pull, format_number(v));
      c.transverse_strain = v;
      json row = {{"name", c.name}, {"pull", pull}, {"transverse_strain", v}};
      try {
        fem::TestModel model = c.model(spec.mesh, spec.rig);
        const fem::SimulationResult sim = fem::simulate(model, *law, P.solver);
        if (!sim.usable()) throw InputError({}, sim.message);
        ident::TestData d = ident::measure(model, sim, data->points, data->point_ids, data->field_kind);
        if (data->edge_displacement.empty()) d.edge_displacement.clear();
        if (data->edge_force.empty()) d.edge_force.clear();
        if (!data->has_field()) d.points.resize(2, 0), d.point_ids.clear(), d.u.resize(0, 0), d.v.resize(0, 0);
        d.sigma = data->sigma;
        d.sigma_u = data->sigma_u, d.sigma_v = data->sigma_v;  // same steps and points as the template
        ident::Experiment e;
        e.tests.push_back(std::move(d));
        const ident::Objective one({model}, e, *law, objective.parameters(), P.objective_options);
        const ident::Evaluation ec = one.evaluate(r.parameters, true);
        if (!ec.ok) throw InputError({}, ec.message);
        candidates.push_back({c.name, ec.jacobian});
        row_of.push_back(rows.size());
      } catch (const std::exception& ex) {
        row["failed"] = ex.what();
      }
      rows.push_back(row);
    }
  }
  if (candidates.empty()) {
    log.print(rows.empty() ? "identify: design: no candidate (it varies the held strain of kind = \"rig\" tests, and "
                             "every candidate strain is tested already or there is no rig test)"
                           : "identify: design: no candidate could be simulated (result.json's \"design\" is null)");
    return nullptr;
  }
  Eigen::VectorXd scale(r.parameters.size());
  for (Eigen::Index k = 0; k < scale.size(); ++k) scale(k) = objective.parameters()[k].resolved_scale();
  const auto criterion =
      spec.design->criterion == "a_optimal" ? ident::DesignCriterion::a_optimal : ident::DesignCriterion::d_optimal;
  const ident::DesignSuggestion s = ident::suggest_test(at_answer.jacobian, r.parameters, scale, candidates, criterion);
  const double sigma =
      r.uncertainty.sigma2 > 0 && std::isfinite(r.uncertainty.sigma2) ? std::sqrt(r.uncertainty.sigma2) : 1.0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    rows[row_of[i]]["score"] = s.score[i];
    rows[row_of[i]]["worst_relative_std_error_with"] = sigma * s.worst_std_error_with[i];
  }
  const std::string& best = candidates[static_cast<std::size_t>(s.best)].name;
  log.print(fmt::format(
      "identify: design ({}): the added test that helps most: {} (worst relative standard error {:.3g} -> {:.3g})",
      spec.design->criterion, best, sigma * s.worst_std_error_now,
      sigma * s.worst_std_error_with[static_cast<std::size_t>(s.best)]));
  return {{"criterion", spec.design->criterion},
          {"worst_relative_std_error_now", sigma * s.worst_std_error_now},
          {"best", best},
          {"candidates", rows}};
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
void plot_history(const fs::path& dir, const IdentifyOutcome& o, const Log& log) {
  const ident::IdentifyResult& r = o.result;
  if (r.history.empty()) return;
  std::string lines;
  for (std::size_t k = 0; k < r.names.size(); ++k) {
    const auto truth = o.truth ? o.truth->value(r.names[k]) : std::nullopt;
    const double ref = truth && *truth != 0 ? *truth : r.parameters(Eigen::Index(k));
    if (ref == 0) continue;
    lines +=
        fmt::format("{}{} using 1:(${}/({:.17g})) with linespoints pt 7 ps 0.5 title \"{}\"",
                    lines.empty() ? "" : ", \\\n  ", io::gnuplot_quote(dir / "history.csv"), k + 3, ref, r.names[k]);
  }
  const std::string by = o.truth ? "truth" : "identified value";
  const std::string body =
      fmt::format(R"gp(set multiplot layout 2,1 title "tricot identify: {0} ({1} Jacobian)" noenhanced
set grid
set key top right
set logscale y
set format y "10^{{%L}}"
set ylabel "objective f"
plot {2} using 1:2 skip 1 with linespoints pt 7 ps 0.5 lc rgb "#000000" title "f (eq. 1)"
unset logscale y
set format y "%g"
set xlabel "LM iteration"
set ylabel "coefficient / {3}"
set key bottom right
plot {4}
unset multiplot
)gp",
                  o.data, ident::to_string(r.jacobian), io::gnuplot_quote(dir / "history.csv"), by, lines);
  plot({.png = dir / "plots" / "history.png", .width = 900, .height = 800}, body, log);
}

// The identified model against the measured edge data, per test: DIR/fit_<test>.csv and plots/fit_<test>.png.
void write_fit(const fs::path& dir, const ident::Objective& objective, const ident::IdentifyResult& r, bool plots,
               const Log& log) {
  const std::vector<fem::SimulationResult> sims = objective.simulations(r.parameters);
  for (std::size_t t = 0; t < objective.models().size(); ++t) {
    const fem::TestModel& m = objective.models()[t];
    const ident::TestData& d = objective.experiment().tests[t];
    const fem::SimulationResult& sim = sims[t];
    if (!sim.usable()) continue;
    io::Table tab;
    tab.columns = {"step", "load", "model_edge_displacement", "model_edge_force"};
    if (!d.edge_displacement.empty()) tab.columns.push_back("edge_displacement");
    if (!d.edge_force.empty()) tab.columns.push_back("edge_force");
    const double scale = objective.force_scale(r.parameters, static_cast<int>(t));  // the specimen's
    for (int k = 0; k < d.steps(); ++k) {
      std::vector<double> row{double(k + 1), d.loads[k], sim.steps[k].edge_displacement,
                              scale * sim.steps[k].edge_force};
      if (!d.edge_displacement.empty()) row.push_back(d.edge_displacement[k]);
      if (!d.edge_force.empty()) row.push_back(d.edge_force[k]);
      tab.rows.push_back(std::move(row));
    }
    const fs::path csv = dir / ("fit_" + m.name + ".csv");
    io::write_atomic(csv, io::to_csv(tab));
    if (!plots || (d.edge_displacement.empty() && d.edge_force.empty())) continue;
    const std::string measured = d.edge_displacement.empty() ? "\"model_edge_displacement\":\"edge_force\""
                                 : d.edge_force.empty()      ? "\"edge_displacement\":\"model_edge_force\""
                                                             : "\"edge_displacement\":\"edge_force\"";
    const std::string body = fmt::format(R"gp(set grid
set key top left
set title "{0}: measured and identified grip response" noenhanced
set xlabel "grip displacement (quarter model), mm"
set ylabel "grip force, N"
plot {1} using {2} with points pt 6 ps 1 title "measured", \
  {1} using "model_edge_displacement":"model_edge_force" with lines lw 2 title "identified model"
)gp",
                                         m.name, io::gnuplot_quote(csv), measured);
    plot({.png = dir / "plots" / ("fit_" + m.name + ".png"), .width = 800, .height = 560}, body, log);
  }
}

namespace {

// DIR/wrinkles_<test>.csv and plots/wrinkles_<test>.png: the wrinkled zone at the last step (the
// element states of fem::element_wrinkles at their reference centroids). Returns the area fractions.
Vec2 write_wrinkles(const fs::path& dir, const fem::TestModel& m, const fem::Law& law, const Eigen::VectorXd& u,
                    bool plots, const Log& log) {
  const std::vector<fem::ElementWrinkles> w = fem::element_wrinkles(m.mesh, law, m.material_angle, u);
  const Vec2 area = fem::wrinkled_and_slack_area(m.mesh, w);
  io::Table tab;
  tab.columns = {"element", "x", "y", "wrinkled", "slack", "angle_deg"};
  const Eigen::VectorXd X = Eigen::Map<const Eigen::VectorXd>(m.mesh.X.data(), m.mesh.X.size());  // as a nodal field
  for (int e = 0; e < m.mesh.elements(); ++e) {
    const Vec2 c = fem::interpolate(m.mesh, {e, fem::element_centre(m.mesh.type)}, X);
    const fem::ElementWrinkles& x = w[std::size_t(e)];
    tab.rows.push_back({double(e), c(0), c(1), x.wrinkled, x.slack, x.angle * 180 / std::numbers::pi});
  }
  const fs::path csv = dir / ("wrinkles_" + m.name + ".csv");
  io::write_atomic(csv, io::to_csv(tab));
  if (!plots) return area;
  const std::string body = fmt::format(R"gp(set size ratio -1
set title "{0} at the last step: wrinkled {1:.1f} %, slack {2:.1f} % of the area" noenhanced
set key below
set xlabel "x (reference), mm"
set ylabel "y, mm"
set cbrange [0:1]
set palette defined (0 "#f0f0f0", 1 "#1f77b4")
set cblabel "wrinkled fraction"
plot {3} using "x":"y":"wrinkled" with points pt 5 ps 1.6 lc palette title "element (colour: wrinkled fraction)", \
  {3} using (column("slack") > 0.5 ? column("x") : 1/0):"y" \
  with points pt 2 ps 1.6 lc rgb "#555555" title "slack element"
)gp",
                                       m.name, 100 * area(0), 100 * area(1), io::gnuplot_quote(csv));
  plot({.png = dir / "plots" / ("wrinkles_" + m.name + ".png"), .width = 700, .height = 640}, body, log);
  return area;
}

}  // namespace

// The identified model against the measured field, per test with a cumulative field (issue 29):
// DIR/fit_field_<test>.csv (step, id, x, y, u, v, model_u, model_v) and plots/fit_field_<test>.png,
// the residual map (model − measured) at the last step, which the report shows with the other plots.
// Returns each test's RMS of |model − measured| over its points and steps, mm (NaN: no field).
std::vector<TestFit> write_fit_field(const fs::path& dir, const ident::Objective& objective,
                                     const ident::IdentifyResult& r, bool plots, const Log& log) {
  const std::vector<fem::SimulationResult> sims = objective.simulations(r.parameters);
  std::vector<TestFit> fits(objective.models().size());
  const std::unique_ptr<fem::Law> law = objective.law_at(r.parameters);
  for (std::size_t t = 0; t < objective.models().size(); ++t) {
    const fem::TestModel& m = objective.models()[t];
    const ident::TestData& d = objective.experiment().tests[t];
    const fem::SimulationResult& sim = sims[t];
    fits[t].name = m.name;
    if (!sim.usable()) continue;
    if (dynamic_cast<const fem::WrinklingLaw*>(law.get()) && !sim.steps.empty()) {
      const Vec2 a = write_wrinkles(dir, m, *law, sim.steps.back().u, plots, log);
      fits[t].wrinkled_area = a(0), fits[t].slack_area = a(1);
    }
    if (!d.edge_force.empty()) {
      double f2 = 0, peak = 0;
      const double scale = objective.force_scale(r.parameters, static_cast<int>(t));
      for (int k = 0; k < d.steps(); ++k)
        f2 += std::pow(scale * sim.steps[std::size_t(k)].edge_force - d.edge_force[std::size_t(k)], 2),
            peak = std::max(peak, std::abs(d.edge_force[std::size_t(k)]));
      fits[t].force_rms_N = std::sqrt(f2 / d.steps()), fits[t].force_peak_N = peak;
    }
    if (!d.has_field() || d.field_kind != ident::FieldKind::cumulative) continue;
    const fem::PointLocator locator(m.mesh);
    io::Table tab;
    tab.columns = {"step", "id", "x", "y", "u", "v", "model_u", "model_v"};
    double s2 = 0;
    int n = 0;
    for (int a = 0; a < d.point_count(); ++a) {
      const Vec2 X = d.points.col(a);
      const auto at = locator.locate(X);
      if (!at) continue;
      for (int k = 0; k < d.steps(); ++k) {
        const Vec2 um = fem::interpolate(m.mesh, *at, sim.steps[std::size_t(k)].u);
        const double u = d.u(k, a), v = d.v(k, a);
        tab.rows.push_back({double(k + 1), double(a < int(d.point_ids.size()) ? d.point_ids[std::size_t(a)] : a), X(0),
                            X(1), u, v, um(0), um(1)});
        s2 += (um(0) - u) * (um(0) - u) + (um(1) - v) * (um(1) - v), ++n;
      }
    }
    if (n > 0) fits[t].points_rms_mm = std::sqrt(s2 / n);
    const fs::path csv = dir / ("fit_field_" + m.name + ".csv");
    io::write_atomic(csv, io::to_csv(tab));
    if (!plots || n == 0) continue;
    const std::string body = fmt::format(R"gp(set grid
set size ratio -1
set title "{0}: field residual (model − measured) at step {1}, ×{2:g}; RMS over all steps {3:.3g} mm" noenhanced
set xlabel "x (quarter model), mm"
set ylabel "y, mm"
plot {4} using (column("step") == {1} ? column("x") : 1/0):"y" \
  :(({2:g})*(column("model_u") - column("u"))):(({2:g})*(column("model_v") - column("v"))) \
  with vectors head filled lw 2 lc rgb "#d62728" title "residual", \
  {4} using (column("step") == {1} ? column("x") : 1/0):"y" with points pt 7 ps 0.8 lc rgb "#333333" title "point"
)gp",
                                         m.name, d.steps(), 10.0, fits[t].points_rms_mm, io::gnuplot_quote(csv));
    plot({.png = dir / "plots" / ("fit_field_" + m.name + ".png"), .width = 700, .height = 640}, body, log);
  }
  return fits;
}

void print_summary(const IdentifyOutcome& o, const fs::path& out, const Log& log) {
  const ident::IdentifyResult& r = o.result;
  const bool truth = o.truth.has_value();
  log.print(r.brief_report());
  std::size_t w = 10;  // the names' column: as wide as the longest (a force scale's `<test>.force_scale`)
  for (const auto& n : r.names) w = std::max(w, n.size());
  std::string head = fmt::format("  {:<{}} {:>13} {:>13} {:>11}", "", w, "start", "identified", "std error");
  if (truth) head += fmt::format(" {:>13} {:>10} {:>7}", "truth", "rel. error", "in s.e.");
  log.print(head);
  for (std::size_t k = 0; k < r.names.size(); ++k) {
    const Eigen::Index i = Eigen::Index(k);
    const double se = i < r.uncertainty.std_error.size() ? r.uncertainty.std_error(i) : std::nan("");
    std::string line =
        fmt::format("  {:<{}} {:>13.6g} {:>13.6g} {:>11.3g}", r.names[k], w, r.start(i), r.parameters(i), se);
    if (truth)
      if (const auto t = o.truth->value(r.names[k]))
        line += fmt::format(" {:>13.6g} {:>9.3g}% {:>7.2f}", *t, 100 * (r.parameters(i) - *t) / std::abs(*t),
                            std::abs(r.parameters(i) - *t) / se);
    log.print(line);
  }
  const ident::Uncertainty& u = r.uncertainty;
  if (u.least_identifiable.size() > 0) {
    std::string dir;
    for (std::size_t k = 0; k < r.names.size(); ++k)
      dir += fmt::format("{}{:+.3f}·δ{}", k ? " " : "", u.least_identifiable(Eigen::Index(k)), r.names[k]);
    log.print(
        fmt::format("  condition number {:.3g}; least identifiable direction (relative): {}", u.condition_number, dir));
  }
  log.print("  -> " + (out / "result.json").string() + ", history.csv, plots/");
}

}  // namespace tricot::project
