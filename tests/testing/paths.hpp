// Paths the tests need: shared benchmark data, the source tree, the built CLI.
#pragma once

#include <filesystem>
#include <string>

namespace tricot::test {

inline std::filesystem::path shared_data() { return TRICOT_SHARED_DATA_DIR; }
inline std::filesystem::path source_dir() { return TRICOT_SOURCE_DIR; }
inline std::string tricot_binary() { return TRICOT_BINARY; }
/// Debian's python3 (with python3-meshio), for reading our files with a real reader.
inline std::string python3() { return TRICOT_PYTHON3; }

/// A fresh empty folder under the build tree for one test's outputs (wherever the test runs from).
inline std::filesystem::path scratch_dir(const std::string& name) {
  auto d = std::filesystem::path(TRICOT_BINARY).parent_path() / "scratch" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace tricot::test
