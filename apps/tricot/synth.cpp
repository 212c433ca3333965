// tricot synth — placeholder until its engine lands.
#include "verbs.hpp"

namespace tricot::cli {

Runner add_synth(CLI::App& app) {
  app.add_subcommand("synth", "Make a synthetic experiment with known coefficients");
  return []() -> ExitCode { throw InputError({}, "tricot synth is not available in this build yet"); };
}

}  // namespace tricot::cli
