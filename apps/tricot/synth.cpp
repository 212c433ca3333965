// tricot synth EXPERIMENT.toml -o DIR: a synthetic experiment with a known law (project/synthesis.hpp).
#include <memory>

#include "console.hpp"
#include "tricot/project/synthesis.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

struct SynthArgs {
  std::string file, out_dir;
  bool verbose = false, quiet = false;
};

constexpr const char* kFooter = R"(
An experiment file is a case file (see `tricot simulate --help`) plus a [synth] table. Use a finer
mesh than the identification's, so that identifying the law is not an inverse crime:

  [mesh]
  width = 50.0                  # full strip, mm
  height = 200.0
  nx = 14                       # finer than the project's 10 × 34
  ny = 48

  [law]
  type = "mooney_rivlin"
  [law.mooney_rivlin]
  terms = ["C10", "C20", "C21", "C03"]
  values = [0.1, -0.025, 0.015, 0.01]     # the truth, N/mm

  [[test]]
  name = "tension"
  kind = "uniaxial"
  control = "force"             # the grip displacement is then a measurement
  load_max = 20.0               # N
  steps = 35

  [synth]
  noise_relative = 0.005        # 0.5 % of each group's RMS
  nx = 6                        # field points across the quarter
  ny = 20                       # and along it

With a [synth.images] table (enabled = true) it also renders camera images of the deformed full
specimen, the fabric's speckle seen by a camera aimed at the specimen centre:

  [synth.images]
  enabled = true
  pixel_size = 0.1              # mm/px
  width = 600                   # px
  height = 600
  noise = 2.0                   # σ, gray levels of 255

It writes DIR/<test>/forces.csv (step, load, edge_displacement, edge_force), DIR/<test>/field.csv
(step, id, x, y, u, v in mm, model coordinates of the quarter specimen) and DIR/truth.json (law,
true coefficients, σ per test, seed, generating mesh) and, with images, DIR/<test>/images/
frame_NNNN.png (frame 0 unloaded) and camera.json (pixel size, centre pixel, axes, step of each
frame). `tricot identify` reads the folder; `tricot dic` reads the images.

Examples:
  tricot synth examples/uniaxial-mooney/experiment.toml -o examples/uniaxial-mooney/experiment
  tricot synth --print-config

Exit codes: 0 ok, 2 bad command line or file, 3 file missing or unreadable, 4 a test did not converge.
)";

}  // namespace

Runner add_synth(CLI::App& app) {
  auto args = std::make_shared<SynthArgs>();
  CLI::App* cmd = app.add_subcommand("synth", "Make a synthetic experiment with known coefficients");
  cmd->footer(kFooter);
  cmd->add_option("experiment", args->file, "The experiment file (TOML); see --print-config")->required();
  cmd->add_option("-o,--out", args->out_dir, "Output folder (the experiment)")->required();
  cmd->add_flag("-v,--verbose", args->verbose, "Log every FE step");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress line");
  add_print_config(cmd, project::synth_schema);
  return [args]() {
    check_out_dir(args->out_dir);
    const io::Node root = io::read_config(project::synth_schema(), args->file);
    Console console(args->verbose, args->quiet);
    project::synthesize(root, args->out_dir, console.log());
    return ExitCode::ok;
  };
}

}  // namespace tricot::cli
