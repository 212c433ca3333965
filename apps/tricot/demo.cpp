// tricot demo [-o DIR]: the paper's §3.3 validation on built-in data (project/demo.hpp).
#include <iostream>
#include <memory>

#include "console.hpp"
#include "tricot/project/demo.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

struct DemoArgs {
  std::string out_dir = "out/demo";
  std::string print_example;
  bool full = false, verbose = false, quiet = false;
};

}  // namespace

Runner add_demo(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Run the main job on built-in data: the paper's Table 1 and Fig. 10 (Mooney–Rivlin validation)");
  cmd->footer(R"(
The paper's §3.3 validation, on data generated at run time:
  1. tricot synth of the uniaxial-mooney case: a clamped rubber strip pulled by a force in 35 steps,
     Mooney–Rivlin C10, C20, C21, C03 known, meshed 14 × 48 Q8 (4282 dofs);
  2. tricot identify of the four coefficients on the paper's mesh size (10 × 34 Q8, 2218 dofs) from
     the grip displacement only, the displacement field only, and both (Table 1), from targets × 0.5;
  3. the ε study of Fig. 10 on the both-data run.
It prints Table 1 with the paper's CPU times (4 h, 94 h, 52 h on a Pentium III 1.2 GHz) beside ours.
--full adds two starting points (× 2, mixed), 0.5 % noise and the finite-difference Jacobian.
The files it runs are in DIR (experiment.toml, <run>/project.toml): rerun any with tricot identify.
Same case by hand: examples/uniaxial-mooney/{experiment,project}.toml.

Exit codes: 0 ok, 4 a Table 1 run did not converge.
)");
  cmd->add_option("-o,--out", args->out_dir, "Output folder")->capture_default_str();
  cmd->add_flag("--full", args->full, "Also the robustness studies (starting points, noise, finite differences)");
  cmd->add_flag("-v,--verbose", args->verbose, "Log lines of the engines");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress lines");
  cmd->add_flag_callback(
      "--print-config",
      [] {
        std::cout << "# tricot demo takes no config file. This is the experiment it synthesises (tricot synth);\n"
                     "# `tricot demo --print-example project` prints its both-data project (tricot identify).\n\n"
                  << project::demo_experiment_toml();
        throw CLI::Success();
      },
      "Print the demo's built-in experiment file and exit");
  cmd->add_option("--print-example", args->print_example,
                  "Print the built-in experiment or project file (examples/uniaxial-mooney/*.toml) and exit")
      ->check(CLI::IsMember({"experiment", "project"}));
  return [args]() {
    if (args->print_example.empty()) {
      check_out_dir(args->out_dir);
      Console console(args->verbose, args->quiet);
      project::DemoRequest req;
      req.out = args->out_dir;
      req.full = args->full;
      req.each_run = [&](const std::function<void(const project::Log&)>& run) {
        Console own(args->verbose, args->quiet);  // its own progress clock and ETA
        run(own.log());
      };
      return project::run_demo(req, console.log()) ? ExitCode::ok : ExitCode::not_converged;
    }
    std::cout << (args->print_example == "experiment" ? project::demo_experiment_toml()
                                                      : project::demo_project_toml({}));
    return ExitCode::ok;
  };
}

}  // namespace tricot::cli
