// tricot experiment LAB.toml -o DIR: a lab's raw files → an experiment for identify (project/lab_experiment.hpp).
#include <memory>

#include "console.hpp"
#include "tricot/project/lab_experiment.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

struct ExperimentArgs {
  std::string file, out_dir;
  bool verbose = false, quiet = false;
};

constexpr const char* kFooter = R"(
A lab file names, per test, the images (a numbered sequence, or a `tricot dic` output folder), where
their times come from, the load-cell log and its columns, and the specimen; [physical] is the camera:

  [experiment]
  field_kind = "cumulative"       # or "incremental" (fixed points, docs/theory.md §7)
  control = "displacement"        # forces.csv load = grip displacement (or "force")

  [physical]
  mm_per_px = 0.1                 # or scale_points = [x0, y0, x1, y1] and scale_distance_mm
  centre_px = [299.5, 299.5]      # the specimen centre (fixed: the camera rides a pantograph)

  [[test]]
  name = "tension"
  images = "tension/images"       # or dic = "out/dic-tension"
  frame_times = "camera_log"      # or "fps" (fps, start_s) or "file_names"
  camera_log = "tension/camera.csv"
  log = "tension/load.txt"        # LabVIEW tab file, decimal comma, header lines: all fine
  time_column = "Temps"
  force_column = "Force"
  crosshead_column = "Traverse"   # "" = none: onset synchronisation
  width_mm = 50.0
  free_length_mm = 200.0

The clock offset between camera and load cell is estimated (cross-correlation of the cross-head with
the grip motion DIC measures, or force onset against motion onset); clock_offset_s in a [[test]]
overrides it. It writes DIR/<test>/forces.csv (step, time, load, edge_displacement, edge_force,
force_per_width), DIR/<test>/field.csv (step, id, x, y, u, v, sigma_u, sigma_v: quarter model, mm),
DIR/<test>/dic/ (when it ran the DIC), DIR/sync.json, DIR/sync.png and DIR/project.toml (a skeleton for
`tricot identify`).

Examples:
  tricot synth examples/lab-uniaxial/experiment.toml -o out/lab-raw
  tricot experiment examples/lab-uniaxial/lab.toml -o out/lab-experiment
  tricot experiment --print-config

Exit codes: 0 ok, 2 bad lab file or log, 3 file missing or unreadable.
)";

}  // namespace

Runner add_experiment(CLI::App& app) {
  auto args = std::make_shared<ExperimentArgs>();
  CLI::App* cmd =
      app.add_subcommand("experiment", "Turn a lab's images, load-cell log and specimen into an experiment");
  cmd->footer(kFooter);
  cmd->add_option("lab", args->file, "The lab file (TOML); see --print-config")->required();
  cmd->add_option("-o,--out", args->out_dir, "Output folder (the experiment)")->required();
  cmd->add_flag("-v,--verbose", args->verbose, "Log every DIC frame");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress line");
  add_print_config(cmd, project::lab_schema);
  return [args]() {
    check_out_dir(args->out_dir);
    const auto spec = project::LabSpec::from_config(io::read_config(project::lab_schema(), args->file));
    Console console(args->verbose, args->quiet);
    project::run_lab_experiment(spec, args->out_dir, console.log());
    return ExitCode::ok;
  };
}

}  // namespace tricot::cli
