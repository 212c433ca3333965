// The one declaration of an engine option's config key (docs/design.md §4.1, "Options and their keys").
//
// An engine's XxxOptions lists its keys in a static keys(): for each, the member it sets, the dotted
// config key ("dic.subset_size": the table, then the key), the help and the range or the words. The
// default is the member's value in the options the verb starts from. From these declarations
// project/spec generates the config file's schema (the checks on reading, `--print-config`, the
// bad-input suite), and the engine's validate() checks the same ranges at its entry (check_ranges):
// whatever checks a key reads its name, range and help from here. An error names the config key
// itself, so the verb only places it at the file's line or the flag that set it (project::Origin).
#pragma once

#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace tricot {

/// One config key: `member` of the options O, of type T (bool, int, double, std::string, an enum, or a
/// list of numbers or words).
template <class O, class T>
struct OptionKey {
  T O::*member;
  std::string_view key;  ///< dotted config key: "dic.subset_size"
  std::string_view help;
  double min = -std::numeric_limits<double>::infinity();  ///< inclusive bounds of a number
  double max = std::numeric_limits<double>::infinity();
  /// The words of a word key; for an enum, words[i] names values[i].
  std::vector<std::string_view> words = {};
  std::vector<T> values = {};

  /// The key in its table: "subset_size".
  std::string_view name() const { return key.substr(key.rfind('.') + 1); }
  /// The table: "dic".
  std::string_view table() const { return key.substr(0, key.rfind('.')); }
};

/// A number's key with its range.
template <class O, class T>
OptionKey<O, T> option(T O::*member, std::string_view key, std::string_view help,
                       double min = -std::numeric_limits<double>::infinity(),
                       double max = std::numeric_limits<double>::infinity()) {
  return {member, key, help, min, max};
}

/// An enum's key: each value with the word the config uses for it.
template <class O, class E>
requires std::is_enum_v<E> OptionKey<O, E> option(E O::*member, std::string_view key, std::string_view help,
                                                  std::vector<std::pair<E, std::string_view>> choices) {
  OptionKey<O, E> k{member, key, help};
  for (const auto& [value, word] : choices) k.values.push_back(value), k.words.push_back(word);
  return k;
}

/// Calls f(k) for each key k of the options O (O::keys()).
template <class O, class F>
void for_each_option(F&& f) {
  std::apply([&](const auto&... k) { (f(k), ...); }, O::keys());
}

/// The word of an enum key's value ("" when it has none).
template <class O, class E>
std::string_view word_of(const OptionKey<O, E>& k, E value) {
  for (std::size_t i = 0; i < k.values.size(); ++i)
    if (k.values[i] == value) return k.words[i];
  return {};
}

namespace detail {
[[noreturn]] void throw_out_of_range(std::string_view key, double got, bool integer, double min, double max);
[[noreturn]] void throw_not_a_word(std::string_view key, std::string_view got,
                                   const std::vector<std::string_view>& words);
}  // namespace detail

/// The declaration of the member `m` of O (a key that O::keys() lists).
template <class O, class T>
OptionKey<O, T> option_of(T O::*m) {
  std::optional<OptionKey<O, T>> found;
  for_each_option<O>([&](const auto& k) {
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(k)>, OptionKey<O, T>>)
      if (k.member == m) found = k;
  });
  if (!found) throw std::logic_error("option_of: a member that keys() does not declare");
  return *found;
}

/// The value that `word` names for the enum key k. Throws InputError at the key when it names none.
template <class O, class E>
E value_of(const OptionKey<O, E>& k, std::string_view word) {
  for (std::size_t i = 0; i < k.words.size(); ++i)
    if (k.words[i] == word) return k.values[i];
  detail::throw_not_a_word(k.key, word, k.words);
}

/// The engine's side of its keys' ranges: throws InputError at the key (`dic.step: out of range (got 0,
/// expected 1 to 1000)`) for the first number of `o` outside its declared range or not finite.
template <class O>
void check_ranges(const O& o) {
  for_each_option<O>([&](const auto& k) {
    using T = std::remove_cvref_t<decltype(o.*k.member)>;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      const double x = static_cast<double>(o.*k.member);
      if (!(x >= k.min && x <= k.max)) detail::throw_out_of_range(k.key, x, std::is_integral_v<T>, k.min, k.max);
    }
  });
}

/// "1 to 1000", ">= 0", "<= 5" or "" (no bound): how a range reads in a message and in --print-config.
std::string range_text(double min, double max);

}  // namespace tricot
