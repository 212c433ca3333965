// tricot simulate's pipeline: the finite-element models of the tests of a case file (docs/theory.md §4–§6)
// and, per test, DIR/<test>/steps.csv, newton.csv, step_NNNN.vtu (+ steps.pvd) and force.png; a
// simple_shear test evaluates the law alone at F = [[1, γ], [0, 1]] (docs/theory.md §4 validation).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tricot/io/config.hpp"
#include "tricot/io/vtu.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/log.hpp"

namespace tricot::project {

/// How to run a case.
struct SimulationRequest {
  std::filesystem::path out;  ///< DIR: one sub-folder per test, DIR/forces.png for several FE tests
  std::string only_test;      ///< run only the test of this name ("" = every test)
  bool vtu = true;            ///< write step_NNNN.vtu and steps.pvd
  int vtu_every = 1;          ///< write every vtu_every-th step's VTU, and the last step's; ≥ 1
  io::VtuFormat vtu_format = io::VtuFormat::binary;
  std::string case_file;  ///< the case file, named by an error about `only_test`
  /// Law coefficients set by name before the run (tricot simulate --law result.json: the identified
  /// law replayed on a project's tests); each a name of the law's coefficient_names().
  std::vector<std::pair<std::string, double>> coefficients;
  std::string coefficients_file;  ///< where they came from, named by an error about them
};

struct SimulationOutcome {
  std::vector<std::string> failures;  ///< one message per test that did not converge (its steps are written)
};

/// Runs the chosen tests of a validated case file (case_spec.hpp). Every test is built before any
/// runs, so a config error stops the run before any work. Throws InputError for a bad case or an
/// unknown `only_test` (key --test), FileError when an output folder cannot be made.
SimulationOutcome run_simulation(const io::Node& root, const SimulationRequest& request, const Log& log);
/// The same from a spec (read from a file or built in code).
SimulationOutcome run_simulation(const CaseSpec& spec, const SimulationRequest& request, const Log& log);

}  // namespace tricot::project
