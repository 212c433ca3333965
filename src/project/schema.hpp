// What the verbs' config files (case_config.cpp, dic_config.cpp) are written with: io's schema names,
// the bound of a key that has no range, and moving an InputError to the key that caused it.
// Include it from .cpp files only: it brings io's schema names into tricot::project.
#pragma once

#include <limits>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/io/config.hpp"

namespace tricot::project {

using io::key;
using io::KeySpec;
using io::Node;
using io::Reals;
using io::SectionSpec;
using io::Strings;

/// Bounds of a key without a range, e.g. a word from a list: key(name, v, help, -kInf, kInf, {choices}).
inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// The message of `e` after its key (`e.what()` is "KEY: problem (got …, expected …)" when `e` names no
/// file), to throw the same problem at another place.
inline std::string problem_of(const InputError& e) {
  std::string s = e.what();
  const std::string k = e.where().key;
  if (!k.empty() && s.rfind(k + ": ", 0) == 0) s = s.substr(k.size() + 2);
  return s;
}

}  // namespace tricot::project
