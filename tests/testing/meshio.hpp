// Reading our VTU files with a real reader: Debian's python3-meshio, run as a child process.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "paths.hpp"

namespace tricot::test {

/// True when python3 (TRICOT_PYTHON3) can import meshio; tests GTEST_SKIP otherwise.
inline bool have_meshio() {
  if (python3().empty()) return false;
  return std::system((python3() + " -c 'import meshio' >/dev/null 2>&1").c_str()) == 0;
}

/// Runs `script` with `m = meshio.read(file)` already done and returns what it prints. Throws
/// std::runtime_error with python's output when it fails.
inline std::string read_with_meshio(const std::filesystem::path& file, const std::string& script) {
  static int counter = 0;
  const auto dir = std::filesystem::current_path() / "scratch" / "meshio";
  std::filesystem::create_directories(dir);
  const auto tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const auto py = dir / ("read_" + tag + ".py"), out = dir / ("read_" + tag + ".out");
  std::ofstream(py) << "import sys, meshio\nm = meshio.read(sys.argv[1])\n" << script;
  const std::string cmd = python3() + " " + py.string() + " '" + file.string() + "' >" + out.string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  std::stringstream text;
  text << std::ifstream(out).rdbuf();
  std::filesystem::remove(py);
  std::filesystem::remove(out);
  if (rc != 0) throw std::runtime_error("python3 + meshio failed: " + text.str());
  return text.str();
}

}  // namespace tricot::test
