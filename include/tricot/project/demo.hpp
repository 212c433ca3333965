// tricot demo: the paper's §3.3 validation (Table 1, Fig. 10) on built-in data. The experiment and
// project files it runs are generated here; examples/uniaxial-mooney/{experiment,project}.toml are
// copies of the default ones (a test keeps them equal), so a user can run the same by hand.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <string>

#include "tricot/project/identification_spec.hpp"
#include "tricot/project/log.hpp"

namespace tricot::project {

/// The experiment file of the `uniaxial-mooney` case: the truth fem::paper_mooney_rivlin_terms(),
/// force-controlled uniaxial strip, 35 steps, generated on 14 × 48 Q8 (4282 dofs); `noise_relative`
/// as in [synth].
std::string demo_experiment_toml(double noise_relative = 0);

/// One identification of the case on the paper's mesh size (10 × 34 Q8, 2218 dofs).
struct DemoProject {
  std::array<double, 4> start{0.05, -0.0125, 0.0075, 0.005};  ///< C10, C20, C21, C03 (truth × 0.5)
  double edge_displacement = 1;                               ///< [data] weights: Table 1's choices
  double field = 1;
  std::string experiment_dir = "experiment";
  ident::JacobianMode jacobian = ident::JacobianMode::exact;
  bool sigma_from_truth = false;
  double epsilon = 1e-12;
};
/// The project of one identification, built in code (what demo runs).
IdentificationSpec demo_project_spec(const DemoProject& p);
/// The project file of demo_project_spec(p), for the user to read and run by hand.
std::string demo_project_toml(const DemoProject& p);

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
