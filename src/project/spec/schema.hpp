// What the config files' schemas (case_spec.cpp, dic_spec.cpp, ...) are written with: io's schema
// names, the bound of a key that has no range, Origin/problem_of (spec.hpp) to place an error, and the
// schema keys generated from an engine's declared options (core/options.hpp): add_keys, read_keys.
// Include it from .cpp files only: it brings io's schema names into tricot::project.
#pragma once

#include <limits>
#include <string>
#include <type_traits>

#include "tricot/core/error.hpp"
#include "tricot/core/options.hpp"
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

/// The schema key of an option declared by an engine, its default `value` (the verb's starting one).
template <class O, class T>
KeySpec key_of(const OptionKey<O, T>& k, const T& value) {
  KeySpec s;
  s.name = k.name(), s.help = k.help, s.min = k.min, s.max = k.max;
  if constexpr (std::is_enum_v<T>) {
    s.default_value = std::string(word_of(k, value));
    for (std::string_view w : k.words) s.choices.emplace_back(w);
  } else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, double> || std::is_same_v<T, std::string> ||
                       std::is_same_v<T, Reals> || std::is_same_v<T, Strings>) {
    s.default_value = value;
    for (std::string_view w : k.words) s.choices.emplace_back(w);
  } else {
    static_assert(std::is_integral_v<T>, "an option is a bool, an integer, a double, a word, an enum or a list");
    s.default_value = static_cast<std::int64_t>(value);
  }
  return s;
}

/// Appends the keys that `defaults`' type declares (O::keys()) to `table`, in their declared order,
/// each with its value in `defaults` as the default: the one source of those keys' schema.
template <class O>
void add_keys(SectionSpec& table, const O& defaults) {
  for_each_option<O>([&](const auto& k) { table.keys.push_back(key_of(k, defaults.*k.member)); });
}

/// A verb's spec struct S (its keys(), an `origin`) read from its validated table.
template <class S>
S read_table(const Node& table);

/// Sets each key that O declares from the validated `table` (read with a schema made by add_keys).
template <class O>
void read_keys(const Node& table, O& o) {
  for_each_option<O>([&](const auto& k) {
    auto& v = o.*k.member;
    using T = std::remove_cvref_t<decltype(v)>;
    const std::string_view name = k.name();
    if constexpr (std::is_enum_v<T>) {
      v = value_of(k, table.string(name));
    } else if constexpr (std::is_same_v<T, bool>) {
      v = table.boolean(name);
    } else if constexpr (std::is_same_v<T, double>) {
      v = table.real(name);
    } else if constexpr (std::is_same_v<T, std::string>) {
      v = table.string(name);
    } else if constexpr (std::is_same_v<T, Reals>) {
      v = table.reals(name);
    } else if constexpr (std::is_same_v<T, Strings>) {
      v = table.strings(name);
    } else {
      v = static_cast<T>(table.integer(name));
    }
  });
}

template <class S>
S read_table(const Node& table) {
  S s;
  read_keys(table, s);
  s.origin = Origin(table);
  return s;
}

}  // namespace tricot::project
