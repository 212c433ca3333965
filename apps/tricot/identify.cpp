// tricot identify PROJECT.toml -o DIR [--resume]: Levenberg–Marquardt identification of a law's
// coefficients from an experiment (docs/theory.md §1–§3, §7, §8; paper §2). Writes DIR/result.json,
// DIR/history.csv, DIR/checkpoint.json (after every accepted step) and DIR/plots/*.png.
#include <memory>

#include "console.hpp"
#include "tricot/mpi/world.hpp"
#include "tricot/project/identification.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

namespace fs = std::filesystem;

struct IdentifyArgs {
  std::string project, out_dir;
  bool resume = false, verbose = false, quiet = false, no_plots = false;
  int kill_after = 0, kill_after_evaluations = 0;
  bool kill_before_publish = false;
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
one column per coefficient), fit_<test>.csv, plots/history.png, plots/fit_<test>.png,
report.html (the lab report: one self-contained page, figures embedded, prints to A4 PDF) with
report.json (every number in it), and checkpoint.json, rewritten after every accepted LM step: `--resume`
continues a killed run from it and reaches the same answer (on a finished run it does nothing). A run
writes in DIR/.tricot-identify/ and moves its files into DIR at the end, replacing the earlier run's.

Examples:
  tricot identify examples/uniaxial-mooney/project.toml -o out/identify
  tricot identify examples/uniaxial-mooney/project.toml -o out/identify --resume
  mpirun -np 4 tricot identify examples/knit-campaign/project-110.toml -o out/kc110
      (the tests spread over 4 MPI ranks; rank 0 runs LM and writes; the same answer bit for bit)

Exit codes: 0 converged, 2 bad command line, project or data, 3 a file or folder missing,
4 ran but did not converge (result.json says why).
)";

}  // namespace

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
  cmd->add_option("--kill-after-evaluations", args->kill_after_evaluations,
                  "Testing aid: kill the run as it starts evaluation N")
      ->group("");
  cmd->add_flag("--kill-before-publish", args->kill_before_publish, "Testing aid: kill the run before publishing")
      ->group("");
  add_print_config(cmd, project::identify_schema);
  return [args]() {
    // Under mpirun every rank builds the objective from the project; rank 0 runs LM and writes, the
    // others evaluate their share of the tests until rank 0 says stop (issue 15). One process
    // otherwise.
    mpi::World world;
    if (world.rank() > 0) {
      project::Project P;
      world.serve([&]() -> const ident::Objective* {
        P = project::build_project(io::read_config(project::identify_schema(), args->project),
                                   fs::path(args->project).parent_path());
        return P.objective.get();
      });
      return ExitCode::ok;  // rank 0 says how the run went; a failed rank's exit would end the job
    }
    check_out_dir(args->out_dir);
    const project::IdentificationSpec spec =
        project::read_identification_spec(io::read_config(project::identify_schema(), args->project));
    Console console(args->verbose, args->quiet);
    project::IdentifyRequest req;
    req.base = fs::path(args->project).parent_path();
    req.out = args->out_dir;
    req.resume = args->resume;
    req.plots = !args->no_plots;
    req.kill_after = args->kill_after;
    req.kill_after_evaluations = args->kill_after_evaluations;
    req.kill_before_publish = args->kill_before_publish;
    req.distribute = [&world](ident::Objective& objective) { world.lead(objective); };
    req.ranks = world.size();
    const project::IdentifyOutcome o = project::run_identification(spec, req, console.log());
    if (args->verbose && world.size() > 1)
      console.log().print(world.traffic().brief_report() + " (" + std::to_string(world.size()) + " ranks)");
    return o.result.converged() ? ExitCode::ok : ExitCode::not_converged;
  };
}

}  // namespace tricot::cli
