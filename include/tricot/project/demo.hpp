// tricot demo --table1: the paper's §3.3 validation (Table 1, Fig. 10) on built-in data. The files it
// runs are examples/uniaxial-mooney/{experiment,project}.toml, built into tricot (examples.hpp); each
// run is the project file with some values changed, written to the run's folder.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "tricot/project/identification_spec.hpp"
#include "tricot/project/log.hpp"

namespace tricot::project {

/// The experiment file of the `uniaxial-mooney` case (examples/uniaxial-mooney/experiment.toml): the
/// truth fem::paper_mooney_rivlin_terms(), force-controlled uniaxial strip, 35 steps, generated on
/// 14 × 48 Q8 (4282 dofs); with `noise_relative`, its [synth] noise_relative changed.
std::string demo_experiment_toml(std::optional<double> noise_relative = std::nullopt);

/// One identification of the case on the paper's mesh size (10 × 34 Q8, 2218 dofs): the example's
/// project (both data, from targets × 0.5, exact Jacobian, ε = 1e-12) with the values given here.
struct DemoProject {
  std::optional<io::Reals> start;           ///< [law.mooney_rivlin] values: C10, C20, C21, C03
  std::optional<double> edge_displacement;  ///< [data] weights: Table 1's choices
  std::optional<double> field;
  std::optional<std::string> experiment_dir;  ///< [experiment] dir
  std::optional<std::string> jacobian;        ///< [identify]
  std::optional<bool> sigma_from_truth;       ///< [experiment]
  std::optional<double> epsilon;              ///< [identify]
};
/// The project file of one identification: examples/uniaxial-mooney/project.toml with p's values.
std::string demo_project_toml(const DemoProject& p);
/// What demo runs: demo_project_toml(p) read as `tricot identify` reads a project file.
IdentificationSpec demo_project_spec(const DemoProject& p);

/// How to run the demo.
struct DemoRequest {
  std::filesystem::path out = "out/demo";  ///< DIR: experiment/, edge/, field/, both/, table1.*, epsilon.csv
  bool full = false;                       ///< also the robustness studies (studies.md)
  /// Runs its argument with the Log of one identification (the CLI gives each run its own progress
  /// clock and ETA); empty = the demo's own Log.
  std::function<void(const std::function<void(const Log&)>&)> each_run;
};
/// (a) synthesises the experiment, (b) identifies the four coefficients from the three data choices
/// of Table 1 (table1.md, table1.csv), (c) the ε study of Fig. 10 (epsilon.csv), and with `full` the
/// robustness studies. Returns whether every Table 1 run converged.
bool run_demo(const DemoRequest& request, const Log& log);

}  // namespace tricot::project
