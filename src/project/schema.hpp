// What the config files (case_spec.cpp, dic_spec.cpp, ...) are written with: io's schema names,
// the bound of a key that has no range, and moving an InputError to the key that caused it.
// Include it from .cpp files only: it brings io's schema names into tricot::project.
#pragma once

#include <limits>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/spec.hpp"

namespace tricot::project {

using io::key;
using io::KeySpec;
using io::Node;
using io::Reals;
using io::SectionSpec;
using io::Strings;

/// Bounds of a key without a range, e.g. a word from a list: key(name, v, help, -kInf, kInf, {choices}).
inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// Rethrows an engine's error at its key in `table`. The engines name a bad option by the config's
/// dotted key ("identify.epsilon", "dic.step"), so the key is looked up in `table`, never renamed.
/// Call it from a handler: an error already located in a file is rethrown unchanged.
[[noreturn]] inline void rethrow_in(const io::Node& table, const InputError& e) {
  if (!e.where().file.empty()) throw;
  std::string key = e.where().key;
  const std::string prefix = table.path().empty() ? std::string() : table.path() + ".";
  if (!prefix.empty() && key.rfind(prefix, 0) == 0) key = key.substr(prefix.size());
  throw InputError(table.where(key), problem_of(e));
}

}  // namespace tricot::project
