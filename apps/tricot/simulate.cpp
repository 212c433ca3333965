// tricot simulate CASE.toml -o DIR: runs the finite-element models of the tests of a case file
// (docs/theory.md §4–§6) and writes, per test, DIR/<test>/steps.csv, step_NNNN.vtu (+ steps.pvd) and force.png.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "console.hpp"
#include "tricot/core/error.hpp"
#include "tricot/io/files.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/identification_spec.hpp"
#include "tricot/project/simulation.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

struct SimulateArgs {
  std::string case_file;
  std::string out_dir;
  std::string only_test;
  bool no_vtu = false;
  int vtu_every = 1;
  bool vtu_ascii = false;
  bool verbose = false;
  bool quiet = false;
  std::string law;  ///< --law result.json: CASE is a project file, its law takes these values
};

// --law: the "parameters" of a tricot identify result.json, by name.
std::vector<std::pair<std::string, double>> identified_parameters(const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(io::read_text(path));
  } catch (const nlohmann::json::exception& e) {
    throw FileError({path, 0, ""}, std::string("not a JSON file: ") + e.what());
  }
  if (!j.contains("parameters") || !j["parameters"].is_object())
    throw InputError({path, 0, "parameters"}, "no \"parameters\" object", "",
                     "a result.json written by tricot identify");
  std::vector<std::pair<std::string, double>> out;
  for (const auto& [name, value] : j["parameters"].items()) {
    if (!value.is_number()) throw InputError({path, 0, "parameters." + name}, "not a number", value.dump(), "a number");
    out.emplace_back(name, value.get<double>());
  }
  return out;
}

constexpr const char* kFooter = R"(
A case file (TOML) holds the specimen, the law, the solver and one or more tests:

  [mesh]                       # the full specimen, mm; the quarter is meshed
  width = 50.0
  height = 200.0
  element = "Q8"
  nx = 6
  ny = 20

  [law]
  type = "mooney_rivlin"
  [law.mooney_rivlin]
  terms = ["C10", "C20", "C21", "C03"]
  values = [0.1, -0.025, 0.015, 0.01]      # N/mm

  [[test]]
  name = "tension"
  kind = "uniaxial"            # uniaxial | biaxial | homogeneous | simple_shear
  load_max = 100.0             # grip displacement of the quarter, mm
  steps = 35

Each test writes DIR/<name>/steps.csv (step, load, edge_displacement, edge_force, force_per_width,
side_force, iterations, cutbacks; simple_shear: gamma, s11, s22, s12), DIR/<name>/newton.csv (step,
iteration, residual_N: the free residual norm after the predictor, iteration 0, and after each Newton
step of the step's last, converged attempt), one step_NNNN.vtu per step
(ParaView: open steps.pvd for the series; point data displacement, cell data cauchy_stress,
green_lagrange_strain and ellipticity, the law's smallest acoustic eigenvalue in N/mm: <= 0 where the
membrane can localise) and force.png. `tricot simulate --print-config` prints
every key with its default, range and help.

With --law result.json, CASE is a project file of tricot identify: its tests run with the identified
coefficients (the forces, fields and VTU of the fit, e.g. to view the identified law's states in
ParaView or to compare a law with another test).

Examples:
  tricot simulate examples/uniaxial-mooney/case.toml -o out/uniaxial
  tricot simulate examples/strip-with-hole/project.toml --law out/swh/result.json -o out/swh-replay
  tricot simulate examples/biaxial-fabric/case.toml -o out/fabric --test wale-c0 --no-vtu

Exit codes: 0 ok, 2 bad command line or case file, 3 case file missing or unreadable,
4 a test did not converge (its converged steps are still written; the message names the step).
)";

}  // namespace

Runner add_simulate(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Run the finite-element models of the tests in CASE.toml (plane-stress membrane, quarter specimen)");
  cmd->footer(kFooter);
  cmd->add_option("case", args->case_file, "The case file (TOML); see --print-config")->required();
  cmd->add_option("-o,--out", args->out_dir, "Output folder: one sub-folder per test")->required();
  cmd->add_option("--test", args->only_test, "Run only the test of this name");
  cmd->add_flag("--no-vtu", args->no_vtu, "Do not write the step_NNNN.vtu fields (steps.csv and plots only)");
  cmd->add_option("--vtu-every", args->vtu_every,
                  "Write the VTU of every N-th step and of the last (default 1: every step)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--vtu-ascii", args->vtu_ascii,
                "VTU arrays as decimal text instead of compressed binary (larger; for reading by eye)");
  cmd->add_flag("-v,--verbose", args->verbose, "Log every step and Newton iteration (residual norms)");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress line");
  cmd->add_option("--law", args->law,
                  "A result.json of tricot identify: CASE is then the project file, and its tests (loads from\n"
                  "the experiment's forces.csv where the project gives none) are run with the identified law");
  add_print_config(cmd, project::case_schema);
  return [args]() {
    check_out_dir(args->out_dir);
    Console console(args->verbose, args->quiet);
    project::SimulationRequest request{args->out_dir,
                                       args->only_test,
                                       !args->no_vtu,
                                       args->vtu_every,
                                       args->vtu_ascii ? io::VtuFormat::ascii : io::VtuFormat::binary,
                                       args->case_file,
                                       {},
                                       {}};
    project::SimulationOutcome o;
    if (args->law.empty()) {
      o = project::run_simulation(io::read_config(project::case_schema(), args->case_file), request, console.log());
    } else {
      request.coefficients = identified_parameters(args->law);
      request.coefficients_file = args->law;
      project::IdentificationSpec spec =
          project::read_identification_spec(io::read_config(project::identify_schema(), args->case_file));
      project::read_loads_from_experiment(spec, std::filesystem::path(args->case_file).parent_path());
      o = project::run_simulation(spec, request, console.log());
    }
    if (!o.failures.empty())  // one line (docs/design.md): the first failure, and how many more
      std::fprintf(
          stderr, "tricot: error: %s: %s%s\n", args->case_file.c_str(), o.failures.front().c_str(),
          o.failures.size() > 1 ? (" (and " + std::to_string(o.failures.size() - 1) + " more tests)").c_str() : "");
    return o.failures.empty() ? ExitCode::ok : ExitCode::not_converged;
  };
}

}  // namespace tricot::cli
