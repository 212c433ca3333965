// What the config files' schemas (case_spec.cpp, dic_spec.cpp, ...) are written with: io's schema
// names, the bound of a key that has no range, and Origin/problem_of (spec.hpp) to place an error.
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

}  // namespace tricot::project
