// tricot demo — placeholder until its engine lands.
#include "verbs.hpp"

namespace tricot::cli {

Runner add_demo(CLI::App& app) {
  app.add_subcommand("demo", "Run the main job on built-in data");
  return []() -> ExitCode { throw InputError({}, "tricot demo is not available in this build yet"); };
}

}  // namespace tricot::cli
