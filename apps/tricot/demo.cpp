// tricot demo [-o DIR]: the whole chain on the §4 campaign (project/campaign_demo.hpp); --table1: the
// paper's §3.3 validation on built-in data (project/demo.hpp).
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "console.hpp"
#include "tricot/project/campaign_demo.hpp"
#include "tricot/project/demo.hpp"
#include "tricot/project/examples.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

struct DemoArgs {
  std::string out_dir = "out/demo";
  std::string print_example;
  bool table1 = false, full = false, small = false, verbose = false, quiet = false;
};

}  // namespace

Runner add_demo(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "demo",
      "Run the main job on built-in data: the §4 campaign from images and load-cell logs to the knit's law "
      "(--table1: the paper's Table 1)");
  cmd->footer(R"(
The whole chain of the paper's Fig. 1 on the §4 campaign of the reference knit, 110 × 110 mm²
(10 rig tests: 5 transverse settings pulled along the wale, 5 along the course):
  1. render  tricot synth: FE of each test with the reference knit, its camera images (1280 × 1024 px,
             the knit's stitches as tracers; set, hold, then 21 pull steps) and its load-cell log
             (100 Hz, noise, tare, a clock offset of 0.37 s);
  2. dic     tricot dic of every test, incremental;
  3. sync    tricot experiment: clock offset and tare from the log, specimen coordinates;
  4. identify  tricot identify: paper14 (14 coefficients) from the field and the grip force, eq. 9;
  5. report  DIR/identify/report.html with the DIC quality, the synchronisation, Tables 4 and 5.
One progress line per stage, a summary of wall and CPU time per stage at the end. The files each
stage ran are in DIR (experiment.toml, dic.toml, lab.toml, experiment/project.toml): rerun any by hand.
The campaign's files are examples/knit-campaign/demo/*.toml.

--table1: the paper's §3.3 validation instead (Table 1 and Fig. 10, Mooney–Rivlin from FE data):
  tricot synth of the uniaxial-mooney case, tricot identify from the grip displacement only, the
  field only and both, from targets × 0.5, and the ε study; --full adds two starting points, 0.5 %
  noise and the finite-difference Jacobian. Same case by hand: examples/uniaxial-mooney/*.toml.

Exit codes: 0 ok, 4 the identification (a Table 1 run) did not converge.
)");
  cmd->add_option("-o,--out", args->out_dir, "Output folder")->capture_default_str();
  cmd->add_flag("--table1", args->table1,
                "The paper's Table 1 and Fig. 10 (Mooney–Rivlin validation) instead of the chain");
  cmd->add_flag("--full", args->full,
                "With --table1 (implied): also the robustness studies (starting points, noise, finite differences)");
  cmd->add_flag("--small", args->small, "A reduced chain (2 tests, small images, 2 LM iterations), for the tests")
      ->group("");
  cmd->add_flag("-v,--verbose", args->verbose, "Log lines of the engines");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress lines");
  cmd->add_flag_callback(
      "--print-config",
      [] {
        const std::string example = project::campaign_example({});
        std::cout << "# tricot demo takes no config file. This is the campaign it synthesises (tricot synth),\n"
                     "# examples/"
                  << example
                  << "/experiment.toml; it writes it, dic.toml, lab.toml and project-template.toml\n"
                     "# to DIR. `tricot demo --print-example experiment|project` prints the --table1 job's files\n"
                     "# (examples/uniaxial-mooney).\n\n"
                  << project::example_file(example + "/experiment.toml");
        throw CLI::Success();
      },
      "Print the demo's built-in campaign (its experiment file) and exit");
  cmd->add_option("--print-example", args->print_example,
                  "Print the --table1 job's experiment or project file (examples/uniaxial-mooney/*.toml) and exit")
      ->check(CLI::IsMember({"experiment", "project"}));
  return [args]() {
    if (args->print_example.empty()) {
      check_out_dir(args->out_dir);
      Console console(args->verbose, args->quiet);
      if (!args->table1 && !args->full) {
        project::CampaignDemoOptions options;
        options.small = args->small;
        const project::CampaignDemoResult r = project::run_campaign_demo(options, args->out_dir, console.log());
        double wall = 0, cpu = 0;
        console.print("stage                 wall (s)    CPU (s)");
        for (const auto& s : r.stages) {
          console.print(fmt::format("{:<20} {:>9.1f} {:>10.1f}", s.name, s.wall_s, s.cpu_s));
          wall += s.wall_s, cpu += s.cpu_s;
        }
        console.print(fmt::format("{:<20} {:>9.1f} {:>10.1f}", "total", wall, cpu));
        console.print("report: " + r.report.string());
        return r.converged ? ExitCode::ok : ExitCode::not_converged;
      }
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
