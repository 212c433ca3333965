// tricot relax LOG -o DIR: a relaxation test's Prony fit and quasi-static verdict (project/relax.hpp).
#include <memory>

#include "console.hpp"
#include "tricot/project/relax.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

struct RelaxArgs {
  project::RelaxSpec spec;
  std::string out_dir;
  double duration = 0, tare = 0;
  CLI::Option *duration_given = nullptr, *tare_given = nullptr;
  bool quiet = false;
};

constexpr const char* kFooter = R"(
Finds the hold of a relaxation test (paper §3.1.1: the knit's characteristic time is about 6 min) in a
load-cell log (CSV or tab-separated, header lines, decimal comma, units in the header: as `tricot
experiment` reads them), fits F(s) = F∞ + Σ F_i exp(−s/τ_i) with 1 to 3 terms and keeps the number of
terms with the lowest BIC. With --duration T it says whether a monotonic test lasting T is quasi-static:
its viscous excess Σ (F_i/F∞)(τ_i/T)(1 − exp(−T/τ_i)) must stay below --tolerance.

It writes DIR/relax.json (hold, every fit, the chosen one, the verdict), DIR/relax.csv (time, hold_time,
force, fit_1..fit_m) and DIR/relax.png.

Examples:
  tricot relax relaxation.txt --time Temps --force Force --crosshead Traverse --duration 1200 -o out/relax
  tricot synth examples/lab-uniaxial/experiment.toml -o out/lab   # writes a relaxation log

Exit codes: 0 ok, 2 bad command line or log, 3 log missing or unreadable, 4 a fit did not converge.
)";

}  // namespace

Runner add_relax(CLI::App& app) {
  auto a = std::make_shared<RelaxArgs>();
  CLI::App* cmd = app.add_subcommand("relax", "Fit a relaxation test (Prony series) and judge quasi-staticity");
  cmd->footer(kFooter);
  cmd->add_option("log", a->spec.log, "The relaxation log")->required();
  cmd->add_option("-o,--out", a->out_dir, "Output folder")->required();
  cmd->add_option("--time", a->spec.time_column, "Time column (s); default time");
  cmd->add_option("--force", a->spec.force_column, "Force column (N); default force");
  cmd->add_option("--crosshead", a->spec.crosshead_column,
                  "Cross-head column; default none (the hold starts at the peak)");
  cmd->add_option("--max-terms", a->spec.options.max_terms, "Prony terms tried, 1 to 3; default 3");
  cmd->add_option("--skip", a->spec.options.skip_s, "Seconds left out after the hold begins; default 0");
  a->tare_given =
      cmd->add_option("--tare", a->tare, "Force at rest, N; default: the mean before the ramp (0 without cross-head)");
  a->duration_given = cmd->add_option("--duration", a->duration, "Duration of a test to judge, s");
  cmd->add_option("--tolerance", a->spec.options.quasi_static_tolerance,
                  "Largest viscous excess of a quasi-static test; default 0.05");
  cmd->add_flag("-q,--quiet", a->quiet, "No summary");
  return [a]() {
    check_out_dir(a->out_dir);
    if (a->tare_given->count()) a->spec.options.tare_N = a->tare;
    if (a->duration_given->count()) a->spec.duration_s = a->duration;
    Console console(false, a->quiet);
    const project::RelaxRun run = project::run_relax(a->spec, a->out_dir, console.log());
    return run.result.termination == lab::RelaxationTermination::converged ? ExitCode::ok : ExitCode::not_converged;
  };
}

}  // namespace tricot::cli
