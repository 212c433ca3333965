// tricot dic — placeholder until its engine lands.
#include "verbs.hpp"

namespace tricot::cli {

Runner add_dic(CLI::App& app) {
  app.add_subcommand("dic", "Digital image correlation over an image sequence");
  return []() -> ExitCode { throw InputError({}, "tricot dic is not available in this build yet"); };
}

}  // namespace tricot::cli
