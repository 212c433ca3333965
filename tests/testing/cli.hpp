// Runs the built `tricot` binary from a test and captures its exit code, stdout and stderr.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "paths.hpp"

namespace tricot::test {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

/// Runs `tricot ARGS` (ARGS is a shell-quoted string) in the current folder.
inline CliRun run_tricot(const std::string& args) {
  static int counter = 0;
  const auto dir = std::filesystem::current_path() / "scratch" / "cli";
  std::filesystem::create_directories(dir);
  const auto tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const auto out = dir / ("out_" + tag), err = dir / ("err_" + tag);
  const std::string cmd = tricot_binary() + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  CliRun r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

}  // namespace tricot::test
