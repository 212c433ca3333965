// tricot: identify the large-strain law of a knitted fabric from a biaxial tension test.
// main() wires the verbs and turns every error into one line on stderr and a documented exit code.
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <system_error>

#include "tricot/mpi/world.hpp"
#include "verbs.hpp"

int tricot_cli_main(int argc, char** argv) {
  using namespace tricot;
  CLI::App app{
      "tricot — identify the large-strain law of a knitted fabric from biaxial tension tests.\n"
      "Chain: images -> digital image correlation -> finite-element models of the tests ->\n"
      "Levenberg–Marquardt fit of the law (Gaied, Drapier & Lun 2007).\n"
      "Run `tricot VERB --help` for each verb, `tricot VERB --print-config` for its commented config."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "tricot 0.1.0");
  const std::vector<std::pair<std::string, cli::Runner>> verbs = {
      {"simulate", cli::add_simulate(app)}, {"identify", cli::add_identify(app)},
      {"dic", cli::add_dic(app)},           {"synth", cli::add_synth(app)},
      {"demo", cli::add_demo(app)},         {"experiment", cli::add_experiment(app)},
      {"relax", cli::add_relax(app)}};
  // Under mpirun every rank parses the same command line: only rank 0 prints (issue 15).
  const bool prints = mpi::launcher_rank() == 0;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (!prints) return e.get_exit_code() == 0 ? 0 : static_cast<int>(ExitCode::usage);
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version, --print-config
    // CLI11's own two lines become the contract's one: `command line: VERB: what (see … --help)`.
    std::string verb;
    for (const CLI::App* s : app.get_subcommands()) verb = s->get_name();
    std::string what = e.what();
    if (verb.empty() && argc > 1)
      what = std::string(argv[1][0] == '-' ? "unknown option '" : "unknown verb '") + argv[1] +
             "' (verbs: simulate, identify, dic, synth, demo, experiment, relax)";
    what += verb.empty() ? "; see tricot --help" : "; see tricot " + verb + " --help";
    for (char& c : what)
      if (c == '\n' || c == '\r') c = ' ';
    std::fprintf(stderr, "tricot: error: %s\n", format_error({"command line", 0, verb}, what, {}, {}).c_str());
    return static_cast<int>(ExitCode::usage);
  }
  // One line whatever the message holds (a multi-line TOML string echoed as `got`, a library's text).
  const auto error = [prints](std::string line) {
    if (!prints) return;
    for (char& c : line)
      if (c == '\n' || c == '\r') c = ' ';
    std::fprintf(stderr, "tricot: error: %s\n", line.c_str());
  };
  try {
    for (const auto& [name, run] : verbs)
      if (app.got_subcommand(name)) return static_cast<int>(run());
  } catch (const InputError& e) {
    error(e.what());
    return static_cast<int>(e.exit_code());
  } catch (const std::filesystem::filesystem_error& e) {
    // A folder that cannot be made or read, e.g. -o naming a file: the contract's FILE: what, exit 3.
    const std::string file = e.path1().empty() ? "filesystem" : e.path1().string();
    error(format_error({file, 0, ""}, e.code().message(), {}, {}));
    return static_cast<int>(ExitCode::input_missing);
  } catch (const std::bad_alloc&) {
    error(format_error({"memory", 0, ""}, "out of memory", {},
                       "a smaller mesh, fewer or smaller images, or a machine with more memory"));
    return static_cast<int>(ExitCode::usage);
  } catch (const std::system_error& e) {
    error(format_error({"system", 0, ""}, e.what(), {}, "fewer threads or more memory"));
    return static_cast<int>(ExitCode::usage);
  } catch (const std::exception& e) {
    error(e.what());
    return static_cast<int>(ExitCode::usage);
  }
  return static_cast<int>(ExitCode::usage);
}
