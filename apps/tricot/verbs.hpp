// The `tricot` program: one file per verb (docs/design.md "Verbs"). Each add_VERB() adds its subcommand,
// options and help to the app and returns the function main() runs when that verb is chosen: flags →
// the verb's spec (tricot_project) → its pipeline → the console. The function returns an ExitCode;
// input errors are thrown as tricot::InputError and reported by main().
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "tricot/core/error.hpp"
#include "tricot/io/config.hpp"

namespace tricot::cli {

using Runner = std::function<ExitCode()>;

Runner add_simulate(CLI::App& app);
Runner add_identify(CLI::App& app);
Runner add_dic(CLI::App& app);
Runner add_synth(CLI::App& app);
Runner add_demo(CLI::App& app);
Runner add_experiment(CLI::App& app);
Runner add_relax(CLI::App& app);

/// Refuses an output folder before any work: empty (InputError) or a file, or under a file (FileError).
void check_out_dir(const std::string& dir);

/// Adds `--print-config` to a verb: prints the verb's fully commented default config and exits 0.
void add_print_config(CLI::App* verb, std::function<io::SectionSpec()> schema);

}  // namespace tricot::cli

/// The whole program (main.cpp): parses argv, runs the verb, and turns every error into one line on
/// stderr and a documented exit code. entry.cpp's main() calls it; the bad-input suite calls it in-process.
int tricot_cli_main(int argc, char** argv);
