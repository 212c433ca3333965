// tricot identify — placeholder until its engine lands.
#include "verbs.hpp"

namespace tricot::cli {

Runner add_identify(CLI::App& app) {
  app.add_subcommand("identify", "Identify the law's coefficients from an experiment (Levenberg–Marquardt)");
  return []() -> ExitCode { throw InputError({}, "tricot identify is not available in this build yet"); };
}

}  // namespace tricot::cli
