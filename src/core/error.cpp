#include "tricot/core/error.hpp"

#include <cstdio>

namespace tricot {

std::string format_error(const Location& where, const std::string& problem, const std::string& got,
                         const std::string& expected) {
  std::string s;
  if (!where.file.empty()) {
    s += where.file;
    if (where.line > 0) (s += ':') += std::to_string(where.line);
    s += ": ";
  }
  if (!where.key.empty()) s += where.key + ": ";
  s += problem;
  if (!got.empty() || !expected.empty()) {
    s += " (";
    if (!got.empty()) s += "got " + got;
    if (!got.empty() && !expected.empty()) s += ", ";
    if (!expected.empty()) s += "expected " + expected;
    s += ")";
  }
  return s;
}

std::string format_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

InputError::InputError(Location where, const std::string& problem, const std::string& got, const std::string& expected)
    : std::runtime_error(format_error(where, problem, got, expected)), where_(std::move(where)), problem_(problem) {}

}  // namespace tricot
