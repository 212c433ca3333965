// tricot: identify the large-strain law of a knitted fabric from a biaxial tension test.
// main() wires the verbs and turns every error into one line on stderr and a documented exit code.
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <iostream>

#include "verbs.hpp"


int main(int argc, char** argv) {
  using namespace tricot;
  CLI::App app{
      "tricot — identify the large-strain law of a knitted fabric from biaxial tension tests.\n"
      "Chain: images -> digital image correlation -> finite-element models of the tests ->\n"
      "Levenberg–Marquardt fit of the law (Gaied, Drapier & Lun 2007).\n"
      "Run `tricot VERB --help` for each verb, `tricot VERB --print-config` for its commented config."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "tricot 0.1.0");
  const std::vector<std::pair<std::string, cli::Runner>> verbs = {
      {"simulate", cli::add_simulate(app)}, {"identify", cli::add_identify(app)}, {"dic", cli::add_dic(app)},
      {"synth", cli::add_synth(app)},       {"demo", cli::add_demo(app)},
      {"experiment", cli::add_experiment(app)}, {"relax", cli::add_relax(app)}};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : static_cast<int>(ExitCode::usage);
  }
  try {
    for (const auto& [name, run] : verbs)
      if (app.got_subcommand(name)) return static_cast<int>(run());
  } catch (const InputError& e) {
    std::fprintf(stderr, "tricot: error: %s\n", e.what());
    return static_cast<int>(e.exit_code());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tricot: error: %s\n", e.what());
    return static_cast<int>(ExitCode::usage);
  }
  return static_cast<int>(ExitCode::usage);
}
