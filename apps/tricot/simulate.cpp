// tricot simulate — placeholder until its engine lands.
#include "verbs.hpp"

namespace tricot::cli {

Runner add_simulate(CLI::App& app) {
  app.add_subcommand("simulate", "Run the finite-element models of the tests in CASE.toml");
  return []() -> ExitCode { throw InputError({}, "tricot simulate is not available in this build yet"); };
}

}  // namespace tricot::cli
