// The lab report of one identification (issue 13): what `tricot identify` writes beside result.json.
// Every number here is also in result.json; the report lays them out for a reader (docs/theory.md §1–§3, §8).
#include "output/identification_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "output/identification_outputs.hpp"
#include "output/json.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

namespace {

// Two-sided 95 % quantile of the normal law: the intervals are J* ± z·s.e., the linearised
// covariance's (docs/theory.md §8), as Ceres's and the paper's uncertainty analysis.
constexpr double kZ95 = 1.959963984540054;

// A plot this run drew (not one an earlier run left in DIR/plots): written after the run began.
bool drawn_by_this_run(const fs::path& png, double wall_seconds) {
  std::error_code ec;
  const auto t = fs::last_write_time(png, ec);
  if (ec) return false;
  const auto began = fs::file_time_type::clock::now() - std::chrono::duration_cast<fs::file_time_type::duration>(
                                                            std::chrono::duration<double>(wall_seconds));
  return t >= began;
}

double at(const Eigen::VectorXd& v, std::size_t k) {
  return Eigen::Index(k) < v.size() ? v(Eigen::Index(k)) : std::nan("");
}

}  // namespace

namespace report {

bool add_eq9(Document& d, const fs::path& result_json) {
  json result;
  try {
    result = json::parse(io::read_text(result_json));
  } catch (const std::exception&) {
    return false;  // the report shows what it can
  }
  if (!result.contains("eq9") || !result["eq9"].is_object()) return false;
  const json& e = result["eq9"];
  const auto num = [](const json& j, const char* key) {
    return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::nan("");
  };
  // The paper's Tables 4 and 5 give the same two numbers per force (docs/theory.md §9, paper §4.3).
  NumericTable t{"Eq. 9 error of the identified surfaces over the whole and the practical strain range",
                 "force",
                 {"whole", "practical", "points (whole)", "points (practical)"},
                 {},
                 {},
                 3,
                 {3, 3, 4, 4}};
  for (const char* f : {"course", "wale"}) {
    if (!e.contains(f)) continue;
    t.labels.push_back(f);
    t.rows.push_back(
        {num(e[f], "whole"), num(e[f], "practical"), num(e[f], "points_whole"), num(e[f], "points_practical")});
  }
  Section& s = d.section(kEq9);
  s.table(std::move(t));
  for (const char* f : {"course", "wale"})
    if (e.contains(f) && e[f].is_object() && e[f].value("computed", true) == false)
      s.callout(std::string("The ") + f + " surface's eq. 9 is not computed: " + e[f].value("reason", std::string()) +
                ". Tests at several transverse strains probe the surface (docs/theory.md §9).");
  if (e.contains("practical") && e["practical"].is_object()) {
    NumericTable p{"Practical strain domain", "strain", {"min", "max"}, {}, {}, 3, {}};
    for (const auto& [k, v] : e["practical"].items())
      if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number()) {
        p.labels.push_back(k);
        p.rows.push_back({v[0].get<double>(), v[1].get<double>()});
      }
    if (!p.rows.empty()) s.table(std::move(p));
  }
  return true;
}

}  // namespace report

report::Document identification_report(const IdentificationSpec& spec, const Project& P, const IdentifyOutcome& o,
                                       const fs::path& out, double wall_seconds) {
  using namespace report;
  const ident::IdentifyResult& r = o.result;
  const ident::Uncertainty& u = r.uncertainty;
  const ident::Objective& objective = *P.objective;
  const ident::IdentifyOptions& opt = P.options;
  const std::size_t n = r.names.size();

  Document d;
  d.title = fmt::format("Identification of {} coefficients of the {} law", n, P.law->name());
  d.subtitle = fmt::format("{} · {} values in {} data groups · {} Jacobian · {}", spec.file.filename().string(),
                           o.residuals, objective.data().groups().size(), ident::to_string(r.jacobian),
                           r.converged() ? "converged" : "NOT converged");

  d.summary = {{"termination", ident::to_string(r.termination)},
               {"objective f", Value(r.objective, 4)},
               {"LM iterations", r.iterations},
               {"coefficients / values", fmt::format("{} / {}", n, o.residuals)},
               {"wall time", Value(wall_seconds, 3, "s")}};

  // Inputs and settings.
  {
    Section& s = d.section(kInputs);
    std::string tests;
    for (const auto& m : P.models) tests += (tests.empty() ? "" : ", ") + m.name;
    KeyValueTable t{"Project and model", {}};
    t.rows = {{"project file", fs::absolute(spec.file).lexically_normal().string()},
              {"experiment folder", spec.experiment.dir},
              {"law", P.law->name()},
              {"tests", tests},
              {"identification mesh", fmt::format("{} dofs (first test)", o.dofs)},
              {"data values N", o.residuals},
              {"coefficients n", int(n)},
              {"truth available", o.truth.has_value()}};
    s.table(std::move(t));
    KeyValueTable lm{"Levenberg–Marquardt settings ([identify])", {}};
    lm.rows = {{"Jacobian", ident::to_string(r.jacobian)},
               {"ε (eq. 2, stop on f)", Value(opt.epsilon, 3)},
               {"δ (eq. 3, stop on the step)", Value(opt.delta, 3)},
               {"function tolerance", Value(opt.function_tolerance, 3)},
               {"gradient tolerance", Value(opt.gradient_tolerance, 3)},
               {"max iterations", opt.max_iterations},
               {"stability test", opt.stability_test},
               {"stability η", Value(opt.stability_eta, 3)},
               {"max restarts", opt.max_restarts},
               {"initial trust-region radius", Value(opt.initial_trust_region_radius, 3)},
               {"line-search trials per step (bounds)", opt.line_search_trials},
               {"active set (bounds)", opt.active_set},
               {"resumed from a checkpoint", opt.resume_from.has_value()}};
    s.table(std::move(lm));
    NumericTable p{"Coefficients to identify ([[parameter]]): start, LM scale and bounds",
                   "coefficient",
                   {"start", "scale", "lower", "upper"},
                   {},
                   {},
                   6,
                   {}};
    for (const auto& q : objective.parameters()) {
      p.labels.push_back(q.name);
      p.rows.push_back({q.start, q.resolved_scale(), q.lower, q.upper});
    }
    s.table(std::move(p));
    NumericTable g{
        "Data groups of f (eq. 1): values N_g, weight w_g, scale s_g, and each group's part of f at J* "
        "and its share",
        "group",
        {"values", "weight", "scale", "scale is σ", "f_g", "share of f"},
        {},
        {},
        6,
        {}};
    const Eigen::VectorXd& res = r.residuals;
    const bool have_r = res.size() >= objective.data().size();
    const double f = have_r ? 0.5 * res.squaredNorm() : 0.0;
    for (const auto& grp : objective.data().groups()) {
      g.labels.push_back(grp.name);
      const double fg = have_r ? 0.5 * res.segment(grp.offset, grp.size).squaredNorm() : NAN;
      g.rows.push_back({double(grp.size), grp.weight, grp.scale, grp.sigma ? 1.0 : 0.0, fg, f > 0 ? fg / f : NAN});
    }
    s.table(std::move(g));
  }

  // LM history.
  {
    Section& s = d.section(kHistory);
    if (!drawn_by_this_run(out / "plots" / "history.png", wall_seconds))
      s.note("No plot of the history (plots turned off, or gnuplot missing): the steps are in history.csv and below.");
    else
      s.figure(fs::path("plots") / "history.png",
               fmt::format("Objective f (eq. 1, log scale) and each coefficient over the {} per LM iteration.",
                           o.truth ? "truth" : "identified value"));
    NumericTable h{"Accepted LM steps", "iteration", {"f"}, {}, {}, 5, {}};
    h.columns.insert(h.columns.end(), r.names.begin(), r.names.end());
    for (const auto& e : r.history) {
      h.labels.push_back(std::to_string(e.iteration));
      std::vector<double> row{e.objective};
      for (Eigen::Index k = 0; k < e.parameters.size(); ++k) row.push_back(e.parameters(k));
      h.rows.push_back(std::move(row));
    }
    if (!h.rows.empty()) s.table(std::move(h));
  }

  // Coefficients.
  {
    Section& s = d.section(kCoefficients);
    s.callout(r.brief_report());
    NumericTable c{"Identified coefficients J* with standard errors and 95 % intervals (J* ± 1.96 s.e.)",
                   "coefficient",
                   {"start", "identified", "std error", "rel. s.e. %", "95 % low", "95 % high"},
                   {},
                   {},
                   6,
                   {}};
    c.column_digits = {4, 6, 3, 2, 6, 6};
    if (o.truth) {
      c.columns.insert(c.columns.end(), {"truth", "rel. error %", "error / s.e."});
      c.column_digits.insert(c.column_digits.end(), {6, 2, 3});
    }
    for (std::size_t k = 0; k < n; ++k) {
      const double J = at(r.parameters, k), se = at(u.std_error, k);
      std::vector<double> row{at(r.start, k), J, se, 100 * se / std::abs(J), J - kZ95 * se, J + kZ95 * se};
      if (o.truth) {
        const auto t = o.truth->value(r.names[k]);
        const double tv = t ? *t : std::nan("");
        row.insert(row.end(), {tv, 100 * (J - tv) / std::abs(tv), std::abs(J - tv) / se});
      }
      c.labels.push_back(r.names[k]);
      c.rows.push_back(std::move(row));
    }
    s.table(std::move(c));
    KeyValueTable t{"Termination", {}};
    t.rows = {{"termination", ident::to_string(r.termination)},
              {"converged", r.converged()},
              {"message", r.message},
              {"objective f(J*)", Value(r.objective, 6)},
              {"LM iterations", r.iterations},
              {"evaluations of r(J)", r.evaluations},
              {"Jacobian evaluations", r.jacobian_evaluations},
              {"failed evaluations", r.failed_evaluations},
              {"stability trials rejected without the FE (barrier ≥ f*)", r.skipped_evaluations},
              {"stability restarts", r.restarts},
              {"stability test passed", r.stability_passed},
              {"covariance from", u.from_sigma ? "measurement σ (docs/theory.md §8)" : "the fit: σ̂² = 2f/(N − n)"},
              {"σ̂²", Value(u.sigma2, 4)},
              {"χ²/dof (with measurement σ; 1 = a fit to the noise)", Value(chi2_per_dof(objective, r), 4)},
              {"model-error factor √(χ²/dof)", Value(std::sqrt(chi2_per_dof(objective, r)), 4)}};
    s.table(std::move(t));
  }

  // Correlation.
  if (u.correlation.rows() == Eigen::Index(n) && n > 1) {
    d.section(kCorrelation)
        .heat_map(HeatMap{"Correlation matrix of the identified coefficients (covariance / (s.e. ⊗ s.e.))", r.names,
                          u.correlation})
        .note(
            "Strong correlations (|ρ| near 1) mark coefficients the data separate poorly; grey cells belong to a "
            "coefficient with an infinite standard error.");
  }

  // Local identifiability at J*.
  if (u.singular_values.size() > 0) {
    Section& s = d.section(kIdentifiability);
    KeyValueTable t{"Sensitivity of the residuals at J* (S·D, relative units)", {}};
    t.rows = {{"condition number", Value(u.condition_number, 4)}, {"full rank", u.full_rank}};
    s.table(std::move(t));
    NumericTable sv{"Singular values of S·D, descending", "", {}, {}, std::vector<std::vector<double>>(1), 4, {}};
    for (Eigen::Index k = 0; k < u.singular_values.size(); ++k) {
      sv.columns.push_back(fmt::format("σ{}", k + 1));
      sv.rows[0].push_back(u.singular_values(k));
    }
    s.table(std::move(sv));
    if (u.least_identifiable.size() == Eigen::Index(n)) {
      NumericTable l{"Least identifiable direction: the relative change δJ_k/|J_k| that changes the residuals least",
                     "",
                     r.names,
                     {},
                     std::vector<std::vector<double>>(1),
                     3,
                     {}};
      for (std::size_t k = 0; k < n; ++k) l.rows[0].push_back(u.least_identifiable(Eigen::Index(k)));
      s.table(std::move(l));
    }
  }

  // [design]: result.json's "design", the added test that would help most.
  try {
    const json result = json::parse(io::read_text(out / "result.json"));
    if (result.contains("design") && result["design"].is_object()) {
      const json& g = result["design"];
      NumericTable t{
          fmt::format("Which added test would help most ({}; best: {}): worst relative standard error now {:.3g}",
                      g.value("criterion", ""), g.value("best", ""),
                      g.value("worst_relative_std_error_now", std::nan(""))),
          "candidate",
          {"held strain", "score", "worst rel. s.e. with it"},
          {},
          {},
          4,
          {}};
      for (const json& c : g["candidates"]) {
        if (c.contains("failed")) continue;
        t.labels.push_back(c.value("name", ""));
        t.rows.push_back({c.value("transverse_strain", std::nan("")), c.value("score", std::nan("")),
                          c.value("worst_relative_std_error_with", std::nan(""))});
      }
      d.section(kIdentifiability).table(std::move(t));
    }
  } catch (const std::exception&) {  // the report shows what it can
  }

  // Fits.
  {
    for (const auto& m : P.models) {
      const fs::path png = fs::path("plots") / ("fit_" + m.name + ".png");  // relative to the report
      if (!drawn_by_this_run(out / png, wall_seconds)) continue;
      d.section(kFit).figure(png, fmt::format("Test {}: measured grip response and the identified model's.", m.name));
    }
  }

  // Eq. 9: result.json's "eq9" when the pipeline wrote one.
  report::add_eq9(d, out / "result.json");

  // Every other plot of DIR/plots (response surfaces, error maps, what later stages draw), by name.
  {
    std::set<fs::path> shown;
    for (const auto& sec : d.sections)
      for (const auto& b : sec.blocks)
        if (const auto* f = std::get_if<Figure>(&b)) shown.insert(f->file.lexically_normal());
    std::vector<fs::path> rest;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(out / "plots", ec))
      if (entry.path().extension() == ".png" && drawn_by_this_run(entry.path(), wall_seconds) &&
          !shown.count((fs::path("plots") / entry.path().filename()).lexically_normal()))
        rest.push_back(fs::path("plots") / entry.path().filename());
    std::sort(rest.begin(), rest.end());
    for (const auto& png : rest) {
      const std::string stem = png.stem().string();
      const bool surface = stem.rfind("eq9", 0) == 0 || stem.find("surface") != std::string::npos;
      d.section(surface ? kSurfaces : "figures", surface ? "Response surfaces and eq. 9 error maps" : "Other figures")
          .figure(png, surface ? fmt::format("{}: identified response surface with the experimental points ({}).", stem,
                                             png.filename().string())
                               : png.filename().string());
    }
  }

  // Wall time.
  {
    NumericTable t{"Wall time per stage", "stage", {"seconds"}, {}, {}, 4, {}};
    t.labels = {"identification (LM)", "outputs (fits, plots, files)", "total (up to the report)"};
    t.rows = {{r.wall_seconds}, {std::max(0.0, wall_seconds - r.wall_seconds)}, {wall_seconds}};
    d.section(kTiming).table(std::move(t));
  }
  return d;
}

void write_identification_report(const IdentificationSpec& spec, const Project& project, const IdentifyOutcome& outcome,
                                 const fs::path& out, double wall_seconds) {
  report::write(identification_report(spec, project, outcome, out, wall_seconds), out);
}

}  // namespace tricot::project
