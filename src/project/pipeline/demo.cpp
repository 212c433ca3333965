// tricot demo [-o DIR]: the paper's §3.3 validation on built-in data (issue 4, docs/design.md).
//   (a) synthesise the `uniaxial-mooney` experiment on a finer mesh than the identification's;
//   (b) identify C10, C20, C21, C03 from the three data choices of the paper's Table 1 (edge only,
//       field only, both) and print Table 1 with the paper's CPU times beside ours;
//   (c) the ε study of the paper's Fig. 10, read off the both-data run (see epsilon_study()).
// --full adds the robustness studies of docs/validation.md: two more starting points, 0.5 %
// noise with measurement σ, and the finite-difference Jacobian.
#include "tricot/project/demo.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/io/files.hpp"
#include "tricot/project/identification.hpp"
#include "tricot/project/synthesis.hpp"

namespace tricot::project {

namespace {

namespace fs = std::filesystem;

const std::array<const char*, 4> kNames{"C10", "C20", "C21", "C03"};

std::array<double, 4> truth() {
  std::array<double, 4> t{};
  const auto terms = fem::paper_mooney_rivlin_terms();
  for (std::size_t k = 0; k < 4; ++k)
    for (const auto& term : terms)
      if (fmt::format("C{}{}", term.i, term.j) == kNames[k]) t[k] = term.C;
  return t;
}

std::string list(const std::array<double, 4>& v) { return io::to_toml(io::Reals(v.begin(), v.end())); }

// A word or a list of words as a TOML basic string ("Q8"; the words here need no escapes).
std::string word(const std::string& w) { return "\"" + w + "\""; }
std::string words(const io::Strings& ws) {
  std::string s;
  for (const auto& w : ws) s += (s.empty() ? "" : ", ") + word(w);
  return "[" + s + "]";
}

// A real as TOML, with the exponent written as a person would ("1e-5", not "1e-05").
std::string real(double x) {
  std::string s = io::to_toml(x);
  for (const char* e : {"e-0", "e+0"})
    if (const auto at = s.find(e); at != std::string::npos) s.erase(at + 2, 1);
  return s;
}

}  // namespace

std::string demo_experiment_toml(double noise_relative) {
  return fmt::format(
      R"(# The paper's generated validation case (§3.3, Fig. 6, Table 1) as a synthetic experiment: a rubber
# strip, clamped in its grips and pulled by a prescribed force in 35 steps, with the four-term
# Mooney–Rivlin law C10, C20, C21, C03 (the truth; fem::paper_mooney_rivlin_terms()). The data are
# generated on a finer mesh (14 × 48 Q8, 4282 dofs) than project.toml identifies on (10 × 34 Q8,
# 2218 dofs, the paper's ~2200), so that the identification is not an inverse crime.
#   tricot synth examples/uniaxial-mooney/experiment.toml -o examples/uniaxial-mooney/experiment
# (`tricot demo` runs the same file, written by src/project/pipeline/demo.cpp.)

[mesh]
width = 50.0        # mm, full strip width
height = 200.0      # mm, free length between the grips
element = "Q8"
nx = 14             # across the quarter (25 mm)
ny = 48             # along the quarter (100 mm)

[law]
type = "mooney_rivlin"

[law.mooney_rivlin]
terms = ["C10", "C20", "C21", "C03"]
values = {}    # N/mm: the truth

[[test]]
name = "tension"
kind = "uniaxial"
control = "force"     # force-controlled: the grip (cross-head) displacement is the edge measurement
grip_holds_x = true   # clamped: the strip necks between its grips
load_max = 20.0       # N on the full strip: it stretches to λ ≈ 1.9
steps = 35

[synth]
noise_relative = {}  # 0 = noise-free; 0.005 = 0.5 % of each group's RMS
seed = 20070101
field = true
field_kind = "cumulative"
nx = 6                # field points across the quarter
ny = 20               # and along it: 120 points, 1 mm inside the edges
inset = 1.0
)",
      list(truth()), io::to_toml(noise_relative));
}

IdentificationSpec demo_project_spec(const DemoProject& p) {
  IdentificationSpec s;
  s.mesh.width = 50, s.mesh.height = 200, s.mesh.type = fem::ElementType::Q8, s.mesh.nx = 10, s.mesh.ny = 34;
  s.law.type = "mooney_rivlin";
  s.law.mooney_rivlin.terms = io::Strings(kNames.begin(), kNames.end());
  s.law.mooney_rivlin.values = io::Reals(p.start.begin(), p.start.end());
  TestSpec t;
  t.name = "tension", t.kind = "uniaxial", t.control = "force", t.grip_holds_x = true;
  t.load_max = 20, t.steps = 35;
  s.test = {t};
  s.experiment.dir = p.experiment_dir;
  s.experiment.field_kind = "cumulative";
  s.experiment.sigma_from_truth = p.sigma_from_truth;
  for (const char* name : kNames) {
    ParameterSpec q;
    q.name = name;
    s.parameter.push_back(q);
  }
  s.data.edge_displacement = p.edge_displacement;
  s.data.field = p.field;
  s.identify.epsilon = p.epsilon;
  s.identify.delta = 1e-5;
  s.identify.jacobian = p.jacobian;
  return s;
}

std::string demo_project_toml(const DemoProject& p) {
  const IdentificationSpec s = demo_project_spec(p);
  const MeshSpec& m = s.mesh;
  const TestSpec& t = s.test.front();
  std::string parameters;
  for (const auto& q : s.parameter) parameters += fmt::format("[[parameter]]\nname = {}\n", word(q.name));
  return fmt::format(
      R"(# Identify the four Mooney–Rivlin coefficients of the paper's validation case (§3.3, Table 1) from
# the synthetic experiment of experiment.toml, on the paper's mesh size (10 × 34 Q8, 2218 dofs).
#   tricot synth examples/uniaxial-mooney/experiment.toml -o examples/uniaxial-mooney/experiment
#   tricot identify examples/uniaxial-mooney/project.toml -o out/uniaxial-mooney
# The start point is [law] below. [data] picks the data of Table 1: edge_displacement (the grip) and
# field; set one weight to 0.0 for "field only" or "edge only". (Written by src/project/pipeline/demo.cpp.)

[mesh]
width = {}
height = {}
element = {}
nx = {}
ny = {}

[law]
type = {}

[law.mooney_rivlin]
terms = {}
values = {}   # N/mm: the start point

[[test]]
name = {}
kind = {}
control = {}
grip_holds_x = {}
load_max = {}
steps = {}

[experiment]
dir = {}
field_kind = {}
sigma_from_truth = {}   # true: σ of the noise synth added, from truth.json (docs/theory.md §8)

{}
[data]
edge_displacement = {}
field = {}

[identify]
epsilon = {}         # the paper's ε (eq. 2)
delta = {}            # the paper's δ (eq. 3)
jacobian = {}
)",
      io::to_toml(m.width), io::to_toml(m.height), word(fem::to_string(m.type)), m.nx, m.ny, word(s.law.type),
      words(s.law.mooney_rivlin.terms), io::to_toml(s.law.mooney_rivlin.values), word(t.name), word(t.kind),
      word(t.control), io::to_toml(*t.grip_holds_x), io::to_toml(t.load_max), t.steps, word(s.experiment.dir),
      word(s.experiment.field_kind), io::to_toml(s.experiment.sigma_from_truth), parameters,
      io::to_toml(s.data.edge_displacement), io::to_toml(s.data.field), real(s.identify.epsilon),
      real(s.identify.delta), word(s.identify.jacobian));
}

namespace {

/// The paper's Table 1 runs (§3.3.1) on a Pentium III 1.2 GHz: CPU time and LM iterations.
struct PaperRun {
  const char* name;
  const char* label;
  double edge, field;  // [data] weights
  double hours;
  int iterations;
};
const PaperRun kTable1[] = {
    {"edge", "edge only (grip displacement)", 1, 0, 4, 101},
    {"field", "field only", 0, 1, 94, 451},
    {"both", "edge + field", 1, 1, 52, 241},
};

struct Run {
  std::string name, label;
  fs::path dir;
  IdentifyOutcome outcome;
};

Run identify_case(const fs::path& out, const std::string& name, const std::string& label, const DemoProject& p,
                  const Log& log, const DemoRequest& args, std::function<void(const ident::Checkpoint&)> observe = {}) {
  Run run{name, label, out / name, {}};
  // The spec is built in code; project.toml is written from it for the user (and not read back).
  IdentificationSpec spec = demo_project_spec(p);
  spec.file = run.dir / "project.toml";
  io::write_atomic(spec.file, demo_project_toml(p));
  IdentifyRequest req;
  req.base = run.dir;
  req.out = run.dir;
  req.print_summary = false;
  req.observe = std::move(observe);
  log.print(fmt::format("-- {}: {}", name, label));
  if (args.each_run) args.each_run([&](const Log& own) { run.outcome = run_identification(spec, req, own); });
  else run.outcome = run_identification(spec, req, log);
  log.print("   " + run.outcome.result.brief_report());
  return run;
}

// The standard error of coefficient k, NaN when the run has none (it failed before its Jacobian).
double std_error(const ident::IdentifyResult& r, std::size_t k) {
  const auto& se = r.uncertainty.std_error;
  return Eigen::Index(k) < se.size() ? se(Eigen::Index(k)) : std::nan("");
}

double relative_error(const ident::IdentifyResult& r, std::size_t k) {
  const double t = truth()[k];
  return (r.parameters(Eigen::Index(k)) - t) / std::abs(t);
}

double max_relative_error(const Eigen::VectorXd& J) {
  double e = 0;
  for (std::size_t k = 0; k < 4; ++k) e = std::max(e, std::abs(J(Eigen::Index(k)) - truth()[k]) / std::abs(truth()[k]));
  return e;
}

// Table 1: target, identified, relative error, std error per coefficient, and the run's cost beside
// the paper's. Printed, and written as table1.md and table1.csv.
void table1(const fs::path& out, const std::vector<Run>& runs, const Log& log) {
  std::string md =
      "| data | coefficient | target | identified | rel. error | std error | iterations | evaluations | wall | "
      "paper CPU (PIII 1.2 GHz) | paper iterations | speed-up |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::string csv =
      "data,coefficient,target,identified,relative_error,std_error,iterations,evaluations,wall_seconds,paper_cpu_"
      "seconds,"
      "paper_iterations,speed_up,termination\n";
  log.print("");
  log.print("Table 1 — Mooney–Rivlin target and identified coefficients, uniaxial tension (paper §3.3.1)");
  log.print(fmt::format("{:<30} {:<4} {:>10} {:>12} {:>10} {:>10} {:>5} {:>5} {:>9} {:>9} {:>9}", "data", "", "target",
                        "identified", "rel.error", "std error", "iter", "eval", "wall", "paper", "speed-up"));
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto& r = runs[i].outcome.result;
    const PaperRun& p = kTable1[i];
    const double paper_s = p.hours * 3600, speed_up = paper_s / r.wall_seconds;
    for (std::size_t k = 0; k < 4; ++k) {
      const bool first = k == 0;
      const double se = std_error(r, k);
      const double J = r.parameters(Eigen::Index(k)), e = relative_error(r, k);
      log.print(fmt::format("{:<30} {:<4} {:>10.6g} {:>12.7g} {:>9.4f}% {:>10.2g} {:>5} {:>5} {:>9} {:>9} {:>9}",
                            first ? p.label : "", kNames[k], truth()[k], J, 100 * e, se,
                            first ? std::to_string(r.iterations) : "", first ? std::to_string(r.evaluations) : "",
                            first ? format_duration(r.wall_seconds) : "", first ? fmt::format("{} h", p.hours) : "",
                            first ? fmt::format("{:.0f}×", speed_up) : ""));
      md += fmt::format("| {} | {} | {:.6g} | {:.7g} | {:+.4f} % | {:.2g} | {} | {} | {} | {} | {} | {} |\n",
                        first ? p.label : "", kNames[k], truth()[k], J, 100 * e, se,
                        first ? std::to_string(r.iterations) : "", first ? std::to_string(r.evaluations) : "",
                        first ? format_duration(r.wall_seconds) : "", first ? fmt::format("{} h", p.hours) : "",
                        first ? std::to_string(p.iterations) : "", first ? fmt::format("{:.0f}×", speed_up) : "");
      csv += fmt::format("{},{},{:.17g},{:.17g},{:.17g},{:.17g},{},{},{:.6g},{},{},{:.6g},{}\n", p.name, kNames[k],
                         truth()[k], J, e, se, r.iterations, r.evaluations, r.wall_seconds, paper_s, p.iterations,
                         speed_up, ident::to_string(r.termination));
    }
  }
  io::write_atomic(out / "table1.md", md);
  io::write_atomic(out / "table1.csv", csv);
}

// The ε study (paper §3.3.2, Fig. 10). A run with tolerance ε stops at its first accepted step with
// f < ε (eq. 2); ε changes nothing else in LM, so that run is the ε = 1e-12 run up to that step. Each
// ε's iterations, evaluations, wall time and coefficients are read off the both-data run's
// checkpoints (without the stability test a stand-alone run adds after it stops). When f never gets
// below ε, the run ends by δ (eq. 3) and the row is the final result.
void epsilon_study(const fs::path& out, const Run& run, const std::vector<ident::Checkpoint>& checkpoints,
                   const Log& log) {
  io::Table t;
  t.columns = {"epsilon", "reached", "iterations", "evaluations", "wall_seconds", "objective", "max_relative_error"};
  for (const char* n : kNames) t.columns.push_back(std::string("relative_error_") + n);
  const auto& r = run.outcome.result;
  log.print("");
  log.print("Fig. 10 — the ε study (both data): a run stopped by eq. (2) at f < ε");
  log.print(fmt::format("{:>8} {:>12} {:>5} {:>5} {:>9} {:>11} {:>14}", "ε", "stopped by", "iter", "eval", "wall", "f",
                        "max rel. error"));
  for (int e = -2; e >= -12; --e) {
    const double eps = std::pow(10.0, e);
    const ident::Checkpoint* hit = nullptr;
    for (const auto& c : checkpoints)
      if (c.objective < eps) {
        hit = &c;
        break;
      }
    const int it = hit ? hit->iterations : r.iterations, ev = hit ? hit->evaluations : r.evaluations;
    const double wall = hit ? hit->wall_seconds : r.wall_seconds, f = hit ? hit->objective : r.objective;
    const Eigen::VectorXd J = hit ? hit->parameters : r.parameters;
    std::vector<double> row{eps, hit ? 1.0 : 0.0, double(it), double(ev), wall, f, max_relative_error(J)};
    for (std::size_t k = 0; k < 4; ++k) row.push_back((J(Eigen::Index(k)) - truth()[k]) / std::abs(truth()[k]));
    log.print(fmt::format("{:>8.0e} {:>12} {:>5} {:>5} {:>9} {:>11.3g} {:>13.3g}%", eps,
                          hit ? "ε (eq. 2)" : "δ (eq. 3)", it, ev, format_duration(wall), f, 100 * row[6]));
    t.rows.push_back(std::move(row));
  }
  const fs::path csv = out / "epsilon.csv";
  io::write_atomic(csv, io::to_csv(t));
  std::string why;
  if (!io::run_gnuplot(fmt::format(R"gp(set terminal pngcairo size 900,800 font ",11"
set output {0}
set datafile separator ","
set multiplot layout 2,1 title "ε study (paper Fig. 10): both data, exact Jacobian, 2218 dofs"
set grid
set logscale x
set format x "10^{{%L}}"
set xrange [1e-13:1e-1]
set key top right
set ylabel "wall time, s"
plot {1} using "epsilon":"wall_seconds" with linespoints pt 7 lw 2 title "tricot (this machine)"
set logscale y
set format y "10^{{%L}}"
set xlabel "convergence tolerance ε (eq. 2)"
set ylabel "max relative error of C_{{ij}}"
set key top left
plot {1} using "epsilon":"max_relative_error" with linespoints pt 7 lw 2 title "max_k |C_k - target| / |target|"
unset multiplot
)gp",
                                   io::gnuplot_quote(out / "plots" / "epsilon.png"), io::gnuplot_quote(csv)),
                       &why))
    log.print("  (no plot: " + why + ")");
}

// Exact Jacobian (FE sensitivities, docs/theory.md §7) against central finite differences at the start point
// of Table 1, and what each costs against one forward FE solve (best of three, this machine).
std::string jacobian_check(const fs::path& out) {
  DemoProject p;
  const Project P = build_project(demo_project_spec(p), out);
  const ident::Problem& problem = *P.objective;
  Eigen::VectorXd J(4);
  for (std::size_t k = 0; k < 4; ++k) J(Eigen::Index(k)) = p.start[k];
  auto best_of_three = [](auto&& f) {
    double best = 1e300;
    for (int i = 0; i < 3; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      f();
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
  };
  ident::Evaluation forward, exact, fd;
  const double t_forward = best_of_three([&] { forward = problem.evaluate(J, false); });
  const double t_exact = best_of_three([&] { exact = problem.evaluate(J, true); });
  ident::JacobianOptions central{ident::JacobianMode::finite_difference, ident::Difference::central, 1e-6, 1};
  const double t_fd = best_of_three([&] { fd = ident::evaluate(problem, J, true, central, &forward); });
  if (!forward.ok || !exact.ok || !fd.ok) return "Jacobian check: an FE run failed at the start point.\n";
  double worst = 0;
  for (Eigen::Index k = 0; k < 4; ++k)
    worst = std::max(worst, (exact.jacobian.col(k) - fd.jacobian.col(k)).norm() / exact.jacobian.col(k).norm());
  const std::string md = fmt::format(
      "\nJacobian at the start point (targets × 0.5, both data, {} residuals): max over coefficients of "
      "‖S_exact − S_fd‖ / ‖S_exact‖ per column = {:.2g} (central differences, step 1e-6 relative).\n"
      "Cost on this machine (best of three, one thread for the differences): one forward FE solve {:.3g} s; "
      "with the exact Jacobian {:.3g} s ({:.2f} × forward); central differences {:.3g} s ({:.1f} × forward).\n",
      exact.r.size(), worst, t_forward, t_exact, t_exact / t_forward, t_fd, t_fd / t_forward);
  return md;
}

// --full: the robustness studies of docs/validation.md.
void studies(const fs::path& out, const Run& both, const Log& log, const DemoRequest& args) {
  const auto T = truth();
  std::vector<Run> runs;
  DemoProject p;
  p.experiment_dir = "../experiment";
  p.start = {2 * T[0], 2 * T[1], 2 * T[2], 2 * T[3]};
  runs.push_back(identify_case(out, "start-x2", "both data, start = targets × 2", p, log, args));
  // Mixed: × (0.5, 0.5, 2, 2). (From × (2, 0.5, 0.5, 2) LM walks into parameters for which the
  // force-controlled strip has no equilibrium and stops there: docs/validation.md.)
  p.start = {0.5 * T[0], 0.5 * T[1], 2 * T[2], 2 * T[3]};
  runs.push_back(identify_case(out, "start-mixed", "both data, start = targets × (0.5, 0.5, 2, 2)", p, log, args));
  p.start = {0.5 * T[0], 0.5 * T[1], 0.5 * T[2], 0.5 * T[3]};
  p.jacobian = "finite_difference";
  runs.push_back(
      identify_case(out, "fd", "both data, forward finite-difference Jacobian (the paper's way)", p, log, args));

  // 0.5 % noise, σ known: the truth should lie within 3 standard errors (docs/theory.md §8).
  const std::string text = demo_experiment_toml(0.005);
  io::write_atomic(out / "experiment-noise.toml", text);
  log.print("-- experiment-noise: the same experiment with 0.5 % noise");
  synthesize(io::parse_config(synth_schema(), text, (out / "experiment-noise.toml").string()), out / "experiment-noise",
             log);
  p.jacobian = "exact";
  p.experiment_dir = "../experiment-noise";
  p.sigma_from_truth = true;
  runs.push_back(identify_case(out, "noise", "both data, 0.5 % noise, σ from truth.json", p, log, args));

  std::string md =
      "| run | termination | iterations | evaluations | wall | C10 | C20 | C21 | C03 | max |error| / std error |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  auto add = [&](const Run& r) {
    const auto& x = r.outcome.result;
    std::string cells;
    double worst = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const double se = std_error(x, k);
      worst = std::max(worst, std::abs(x.parameters(Eigen::Index(k)) - T[k]) / se);
      cells += fmt::format(" {:.7g} ({:+.4f} %) |", x.parameters(Eigen::Index(k)), 100 * relative_error(x, k));
    }
    md += fmt::format("| {} | {} | {} | {} | {:.3g} s |{} {:.2f} |\n", r.label, ident::to_string(x.termination),
                      x.iterations, x.evaluations, x.wall_seconds, cells, worst);
  };
  add(both);
  for (const auto& r : runs) add(r);
  const auto& noise = runs.back().outcome.result;
  if (noise.uncertainty.correlation.rows() != 4 || noise.uncertainty.least_identifiable.size() != 4) {
    md += "\nThe noise run has no covariance (it failed before its Jacobian).\n";
    io::write_atomic(out / "studies.md", md);
    return;
  }
  md +=
      "\nCorrelation matrix of the 0.5 % noise run (C10, C20, C21, C03):\n\n| | C10 | C20 | C21 | C03 "
      "|\n|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < 4; ++i) {
    md += fmt::format("| {} |", kNames[i]);
    for (std::size_t k = 0; k < 4; ++k)
      md += fmt::format(" {:+.3f} |", noise.uncertainty.correlation(Eigen::Index(i), Eigen::Index(k)));
    md += "\n";
  }
  md += "\nStandard errors (relative): ";
  for (std::size_t k = 0; k < 4; ++k)
    md += fmt::format("{}{} {:.3g} %", k ? ", " : "", kNames[k], 100 * std_error(noise, k) / std::abs(T[k]));
  md += fmt::format(".\nCondition number {:.3g}; least identifiable direction (relative changes):",
                    noise.uncertainty.condition_number);
  for (std::size_t k = 0; k < 4; ++k)
    md += fmt::format(" {:+.3f} δ{}", noise.uncertainty.least_identifiable(Eigen::Index(k)), kNames[k]);
  md += ".\n";
  md += jacobian_check(out);
  io::write_atomic(out / "studies.md", md);
  log.print("");
  log.print("Robustness studies (written to studies.md):");
  log.print(md);
}

}  // namespace

bool run_demo(const DemoRequest& args, const Log& log) {
  const fs::path out = args.out;
  const auto t0 = std::chrono::steady_clock::now();
  fs::create_directories(out / "plots");

  // (a) The experiment, on the finer mesh.
  log.print("-- experiment: tricot synth of the uniaxial-mooney case (paper §3.3), noise-free");
  const std::string experiment = demo_experiment_toml();
  io::write_atomic(out / "experiment.toml", experiment);
  synthesize(io::parse_config(synth_schema(), experiment, (out / "experiment.toml").string()), out / "experiment", log);

  // (b) Table 1, and (c) the ε study from the both-data run.
  std::vector<Run> runs;
  std::vector<ident::Checkpoint> checkpoints;
  for (const PaperRun& p : kTable1) {
    DemoProject proj;
    proj.experiment_dir = "../experiment";
    proj.edge_displacement = p.edge;
    proj.field = p.field;
    auto observe = std::string(p.name) == "both" ? std::function<void(const ident::Checkpoint&)>(
                                                       [&](const ident::Checkpoint& c) { checkpoints.push_back(c); })
                                                 : nullptr;
    runs.push_back(identify_case(out, p.name, p.label, proj, log, args, observe));
  }
  table1(out, runs, log);
  epsilon_study(out, runs.back(), checkpoints, log);
  if (args.full) studies(out, runs.back(), log, args);

  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log.print("");
  log.print(fmt::format("demo done in {}. Everything is in {}:", format_duration(total), (out / "").string()));
  log.print("  table1.md, table1.csv            Table 1 (target, identified, errors, cost beside the paper's)");
  log.print("  epsilon.csv, plots/epsilon.png   the ε study (Fig. 10)");
  log.print("  edge/, field/, both/             each run: project.toml, result.json, history.csv, plots/history.png");
  log.print("  experiment/, experiment.toml     the synthetic experiment and the file that made it");
  if (args.full) log.print("  studies.md                       starting points, 0.5 % noise, finite differences");
  bool ok = true;
  for (const auto& r : runs) ok = ok && r.outcome.result.converged();
  return ok;
}

}  // namespace tricot::project
