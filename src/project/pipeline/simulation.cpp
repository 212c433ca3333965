// tricot simulate's pipeline (see simulation.hpp).
#include "tricot/project/simulation.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <map>
#include <optional>

#include "output/plot.hpp"
#include "tricot/fem/corotational.hpp"
#include "tricot/fem/element.hpp"
#include "tricot/ident/problem.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/vtu.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/fem_vtu.hpp"
#include "tricot/project/output_dir.hpp"

namespace tricot::project {

namespace {

namespace fs = std::filesystem;

/// A specimen k times as stiff as `inner`: k P, k ∂P/∂F, k ∂P/∂c (a test's force scale from result.json,
/// docs/theory.md §2). Under a displacement-controlled grip its displacements are the law's, its
/// forces and stresses k times.
class ScaledLaw final : public fem::Law {
 public:
  ScaledLaw(const fem::Law& inner, double k) : inner_(inner.clone()), k_(k) {}
  std::string name() const override { return inner_->name(); }
  std::vector<std::string> coefficient_names() const override { return inner_->coefficient_names(); }
  Eigen::VectorXd coefficients() const override { return inner_->coefficients(); }
  void set_coefficients(const Eigen::VectorXd& c) override { inner_->set_coefficients(c); }
  bool linear_in_coefficients() const override { return inner_->linear_in_coefficients(); }
  void evaluate(const fem::LawInput& in, const fem::LawRequest& req, fem::LawOutput& out) const override {
    inner_->evaluate(in, req, out);
    out.P *= k_;
    if (req.tangent) out.A *= k_;
    for (Mat2& d : out.dP_dc) d *= k_;
  }
  std::unique_ptr<fem::Law> clone() const override { return std::make_unique<ScaledLaw>(*inner_, k_); }

 private:
  std::unique_ptr<fem::Law> inner_;
  double k_;
};

// The output folder of a test; FileError (exit 3) when it cannot be made.
void make_dir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw FileError({dir.string(), 0, ""}, "cannot create the output folder: " + ec.message());
}

std::string step_file(std::size_t k) { return fmt::format("step_{:04d}.vtu", k); }

// Removes step_NNNN.vtu files of an earlier run beyond the `kept` steps just written (and its
// steps.pvd when none was written).
void remove_stale_steps(const fs::path& dir, std::size_t kept) {
  std::error_code ec;
  if (kept == 0) fs::remove(dir / "steps.pvd", ec);
  io::remove_numbered_files(dir, "step_", ".vtu", static_cast<long>(kept) + 1);
}

// Step k's VTU (1-based) when k is a multiple of `every` or the last step; an earlier run's file of a
// step not written now is removed, so the folder and steps.pvd agree.
void write_vtus(const fs::path& dir, const fem::TestModel& test, const fem::Law& law,
                const std::vector<Eigen::VectorXd>& u, const std::vector<double>& time, const SimulationRequest& args) {
  std::vector<io::PvdEntry> series;
  for (std::size_t k = 0; k < u.size(); ++k) {
    const std::size_t step = k + 1;
    if (step % args.vtu_every != 0 && step != u.size()) {
      std::error_code ec;
      fs::remove(dir / step_file(step), ec);
      continue;
    }
    io::write_vtu(dir / step_file(step), fem_vtu_grid(test.mesh, u[k], law, test.material_angle), args.vtu_format);
    series.push_back({time[k], step_file(step)});
  }
  io::write_pvd(dir / "steps.pvd", series);
}

// --- FE tests ---------------------------------------------------------------------------------------

struct TestOutcome {
  bool converged = true;
  std::string message;
};

// `args.out` is the staging folder (OutputDir); messages name the files where they end up, in `shown`.
TestOutcome run_fe_test(const fem::TestModel& test, const fem::Law& law, const fem::SolveOptions& options,
                        const SimulationRequest& args, const fs::path& shown, const Log& log) {
  const fs::path dir = args.out / test.name;
  const fem::SimulationResult r = fem::simulate(test, law, options, log.reporter());

  io::Table t;
  t.columns = {"step",       "load",       "edge_displacement", "edge_force", "force_per_width",
               "side_force", "iterations", "cutbacks"};
  // Models of any mesh: each named boundary's resultant (N), after the quarter's columns.
  const std::vector<std::string> resultants =
      test.has_conditions() ? test.resultant_boundaries() : std::vector<std::string>{};
  for (const std::string& b : resultants) t.columns.insert(t.columns.end(), {"resultant_x_" + b, "resultant_y_" + b});
  io::Table newton;  // the residual norm after the predictor (iteration 0) and after each Newton step
  newton.columns = {"step", "iteration", "residual_N"};
  std::vector<Eigen::VectorXd> u;
  std::vector<double> time;
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const auto& s = r.steps[k];
    t.rows.push_back({double(k + 1), s.load, s.edge_displacement, s.edge_force, s.force_per_width, s.side_force,
                      double(s.iterations), double(s.cutbacks)});
    for (std::size_t b = 0; b < resultants.size(); ++b)
      t.rows.back().insert(t.rows.back().end(), {s.resultants[b].x(), s.resultants[b].y()});
    for (std::size_t i = 0; i < s.residuals.size(); ++i)
      newton.rows.push_back({double(k + 1), double(i), s.residuals[i]});
    u.push_back(s.u);
    time.push_back(s.load);
  }
  make_dir(dir);
  if (args.vtu) write_vtus(dir, test, law, u, time, args);
  remove_stale_steps(dir, !args.vtu ? 0 : u.size());
  io::write_atomic(dir / "steps.csv", io::to_csv(t));
  io::write_atomic(dir / "newton.csv", io::to_csv(newton));

  if (!r.steps.empty()) {
    const bool force = test.control == fem::GripControl::force;
    const std::string body =
        fmt::format(R"gp(set key top left
set grid
set title "{}: force per unit initial width"
set xlabel "grip displacement (quarter model), mm"
set ylabel "force per width, N/mm"
plot {} using "edge_displacement":"force_per_width" with linespoints pt 7 ps 0.6 title "{}"
)gp",
                    test.name, io::gnuplot_quote(dir / "steps.csv"), force ? "force-controlled" : "FE");
    plot({.png = dir / "force.png", .width = 800, .height = 560, .enhanced = false}, body, log);
  }

  const std::string where = (shown / test.name / "").string();
  log.print(test.name + ": " + r.brief_report() + " -> " + where);
  return {r.usable(), r.message};
}

// --- simple shear: the law at F = [[1, γ], [0, 1]] (docs/theory.md §4 validation) ------------------------------

TestOutcome run_simple_shear(const fem::TestModel& test, const fem::Law& law, const LawSpec& law_spec,
                             const SimulationRequest& args, const fs::path& shown, const Log& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path dir = args.out / test.name;
  io::Table t;
  t.columns = {"gamma", "s11", "s22", "s12"};
  std::vector<Eigen::VectorXd> u;
  TestOutcome outcome;
  fem::LawInput in;
  in.Q = fem::material_axes(test.material_angle);
  fem::LawOutput out;
  for (std::size_t k = 0; k < test.loads.size(); ++k) {
    const double gamma = test.loads[k];
    in.F << 1, gamma, 0, 1;
    law.evaluate(in, {false, false}, out);
    const Mat2 s = fem::Law::cauchy(in.F, out.P);
    if (!s.allFinite()) {
      outcome = {false, fmt::format("test '{}': step {} of {} (gamma {:.6g}): the law returned a non-finite stress",
                                    test.name, k + 1, test.loads.size(), gamma)};
      break;
    }
    t.rows.push_back({gamma, s(0, 0), s(1, 1), s(0, 1)});
    // The element's nodes follow u = (γ Y, 0): every Gauss point sees the same F.
    Eigen::VectorXd uk = Eigen::VectorXd::Zero(test.mesh.dofs());
    for (int a = 0; a < test.mesh.nodes(); ++a) uk(2 * a) = gamma * test.mesh.X(1, a);
    u.push_back(std::move(uk));
  }
  make_dir(dir);
  if (args.vtu) {
    std::vector<double> time;
    for (const auto& row : t.rows) time.push_back(row[0]);
    write_vtus(dir, test, law, u, time, args);
  }
  remove_stale_steps(dir, !args.vtu ? 0 : u.size());
  io::write_atomic(dir / "steps.csv", io::to_csv(t));

  // Beside the law: the closed forms of three objective rates for an isotropic corotational law.
  std::string extra;
  const CorotationalSpec& co = law_spec.corotational;
  const bool isotropic = law_spec.type == "corotational" && co.moduli == "isotropic";
  if (isotropic && !t.rows.empty()) {
    const double G = co.G, g_max = t.rows.back()[0], g_min = std::min(0.0, t.rows.front()[0]);
    io::Table c;
    c.columns = {"gamma", "log_s12", "log_s11", "jaumann_s12", "jaumann_s11", "green_naghdi_s12", "green_naghdi_s11"};
    constexpr int kSamples = 400;
    for (int i = 0; i <= kSamples; ++i) {
      const double g = g_min + (g_max - g_min) * i / kSamples;
      const auto L = fem::simple_shear_log_rate(G, g), J = fem::simple_shear_jaumann(G, g),
                 N = fem::simple_shear_green_naghdi(G, g);
      c.rows.push_back({g, L.s12, L.s11, J.s12, J.s11, N.s12, N.s11});
    }
    io::write_atomic(dir / "closed_form.csv", io::to_csv(c));
    const std::string cf = io::gnuplot_quote(dir / "closed_form.csv");
    extra = fmt::format(
        R"gp(, {0} using "gamma":"log_s12" with lines lw 1 lc rgb "#1f77b4" dt 2 title "σ12 log rate, closed form", \
  {0} using "gamma":"log_s11" with lines lw 1 lc rgb "#d62728" dt 2 title "σ11 log rate, closed form", \
  {0} using "gamma":"jaumann_s12" with lines lc rgb "#999999" title "σ12 Jaumann: G sin γ", \
  {0} using "gamma":"green_naghdi_s12" with lines lc rgb "#2ca02c" title "σ12 Green–Naghdi", \
  {0} using "gamma":"jaumann_s11" with lines lc rgb "#999999" dt 3 title "σ11 Jaumann", \
  {0} using "gamma":"green_naghdi_s11" with lines lc rgb "#2ca02c" dt 3 title "σ11 Green–Naghdi")gp",
        cf);
  }
  if (!t.rows.empty()) {
    const std::string body = fmt::format(R"gp(set key below maxrows 4
set grid
set title "{0}: simple shear F = [[1, γ], [0, 1]], Cauchy stress"
set xlabel "shear γ"
set ylabel "σ, N/mm"
plot {1} using "gamma":"s12" with points pt 6 ps 0.8 lc rgb "#1f77b4" title "σ12 tricot ({2})", \
  {1} using "gamma":"s11" with points pt 4 ps 0.7 lc rgb "#d62728" title "σ11 tricot"{3}
)gp",
                                         test.name, io::gnuplot_quote(dir / "steps.csv"), law.name(), extra);
    plot({.png = dir / "force.png", .width = 900, .height = 680, .enhanced = false}, body, log);
  }

  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!t.rows.empty()) {
    const auto& last = t.rows.back();
    log.print(
        fmt::format("{}: {} steps (the law at F = [[1, γ], [0, 1]]), {}; at γ = {:.5g}: s12 = {:.6g}, "
                    "s11 = {:.6g} N/mm -> {}",
                    test.name, t.rows.size(), format_duration(seconds), last[0], last[3], last[1],
                    (shown / test.name / "").string()));
  }
  return outcome;
}

// DIR/forces.png: every FE test's force per width on one plot.
void plot_all(const Log& log, const fs::path& dir, const std::vector<std::string>& tests) {
  std::string curves;
  for (const auto& t : tests)
    curves +=
        fmt::format("{}{} using \"edge_displacement\":\"force_per_width\" with linespoints pt 7 ps 0.4 title \"{}\"",
                    curves.empty() ? "" : ", \\\n  ", io::gnuplot_quote(dir / t / "steps.csv"), t);
  const std::string body = fmt::format(R"gp(set key top left
set grid
set title "force per unit initial width, every test"
set xlabel "grip displacement (quarter model), mm"
set ylabel "force per width, N/mm"
plot {}
)gp",
                                       curves);
  plot({.png = dir / "forces.png", .width = 900, .height = 600, .enhanced = false}, body, log);
}

}  // namespace

SimulationOutcome run_simulation(const io::Node& root, const SimulationRequest& args, const Log& log) {
  return run_simulation(CaseSpec::from_config(root), args, log);
}

SimulationOutcome run_simulation(const CaseSpec& spec, const SimulationRequest& args, const Log& log) {
  spec.check_tests();
  const auto law = spec.law.law(spec.mesh.region_names());
  std::map<std::string, double> force_scale;  // per test name: its specimen's `<test>.force_scale`
  if (!args.coefficients.empty()) {  // --law: the identified values, by name
    const std::vector<std::string> known = law->coefficient_names();
    Eigen::VectorXd c = law->coefficients();
    for (const auto& [name, value] : args.coefficients) {
      if (const std::string test = ident::force_scale_test(name); spec.find_test(test)) {
        force_scale[test] = value;
        continue;
      }
      const auto at = std::find(known.begin(), known.end(), name);
      if (at == known.end()) {
        const std::string hint = io::closest_name(name, known);
        throw InputError({args.coefficients_file, 0, "parameters." + name},
                         "not a coefficient of the project's law" +
                             (hint.empty() ? std::string() : "; did you mean '" + hint + "'?"),
                         "\"" + name + "\"", "a result.json of this project");
      }
      c(at - known.begin()) = value;
    }
    try {
      law->set_coefficients(c);
    } catch (const InputError& e) {
      throw InputError({args.coefficients_file, 0, "parameters"}, problem_of(e));
    }
  }
  const fem::SolveOptions options = spec.solver.options();

  // Build every chosen test first: a config error stops the run before any work.
  std::vector<std::pair<const TestSpec*, fem::TestModel>> tests;
  io::Strings names;
  for (const auto& t : spec.test) {
    names.push_back(t.name);
    if (!args.only_test.empty() && t.name != args.only_test) continue;
    tests.emplace_back(&t, t.model(spec.mesh, spec.rig));
  }
  if (tests.empty()) {
    const std::string hint = io::closest_name(args.only_test, names);
    std::string all;
    for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
    throw InputError({args.case_file, 0, "--test"},
                     "no test of that name" + (hint.empty() ? std::string() : "; did you mean '" + hint + "'?"),
                     "\"" + args.only_test + "\"", "one of " + all);
  }

  // Written in a staging folder, published at the end (issue 14); a run of one test (--test)
  // replaces that test's files only.
  OutputDir output(args.out, "simulate");
  SimulationRequest staged = args;
  staged.out = output.staging();
  std::vector<std::string> failures, fe_tests;
  for (const auto& [test, model] : tests) {
    const bool shear = test->test_kind() == TestKind::simple_shear;
    const auto scaled = force_scale.find(model.name);
    const std::optional<ScaledLaw> scaled_law =
        scaled == force_scale.end() ? std::nullopt : std::optional<ScaledLaw>(std::in_place, *law, scaled->second);
    const fem::Law& specimen = scaled_law ? static_cast<const fem::Law&>(*scaled_law) : *law;
    const TestOutcome o = shear ? run_simple_shear(model, specimen, spec.law, staged, args.out, log)
                                : run_fe_test(model, specimen, options, staged, args.out, log);
    if (!o.converged) failures.push_back(o.message);
    if (!shear) fe_tests.push_back(model.name);
  }
  if (fe_tests.size() > 1) plot_all(log, staged.out, fe_tests);
  if (args.only_test.empty()) output.publish();
  else output.publish({args.only_test + "/"});
  return {failures};
}

}  // namespace tricot::project
