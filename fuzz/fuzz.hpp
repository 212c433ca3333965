// Shared by the libFuzzer harnesses (issue 14): a scratch file per process for the readers that take
// a path, and the contract every harness checks: bad input is a tricot::InputError (FileError
// included); anything else escaping (another exception, a crash, a sanitizer report) is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "tricot/core/error.hpp"

namespace tricot::fuzz {

/// /tmp/tricot-fuzz-PID/NAME, its folder created.
inline std::filesystem::path scratch(const std::string& name) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("tricot-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir / name;
}

/// Writes the bytes to `path` (replacing it) and returns the path.
inline std::filesystem::path write(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
  return path;
}

inline std::string_view view(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace tricot::fuzz
