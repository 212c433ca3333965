// TOML configuration with a declared schema: every key has a type, a default, a range and a help text
// (docs/design.md). The same schema reads a file (unknown keys are errors with a "did you mean" hint,
// every bad value names FILE:LINE: KEY) and prints the fully commented default config
// (`tricot VERB --print-config`).
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "tricot/core/error.hpp"

namespace tricot::io {

using Strings = std::vector<std::string>;
using Reals = std::vector<double>;
/// What a key can hold. The schema's default fixes the type of each key.
using Value = std::variant<bool, std::int64_t, double, std::string, Reals, Strings>;

/// One key of a config table.
struct KeySpec {
  std::string name;
  Value default_value;
  std::string help;
  /// Inclusive bounds for numbers (and each element of a list of numbers).
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  /// Allowed words for a string key (empty = any string).
  Strings choices;
  /// The list of numbers must be strictly increasing (load steps, for instance).
  bool increasing = false;
  /// A string key that also takes a number (a word for some entries, a size for others, e.g. the
  /// side of [[test]]: free or guide, or the rig's specimen side in mm); read it with Node::value().
  bool or_number = false;
  /// An alternative to other keys, read only when the user writes it (e.g. E and ν instead of μ and
  /// λ): --print-config prints it commented out, so that the printed config runs as it is.
  bool alternative = false;
};

/// A KeySpec in one line, as the verbs' schemas write them.
inline KeySpec key(std::string name, Value default_value, std::string help,
                   double min = -std::numeric_limits<double>::infinity(),
                   double max = std::numeric_limits<double>::infinity(), Strings choices = {},
                   bool increasing = false) {
  return KeySpec{std::move(name), std::move(default_value), std::move(help), min, max, std::move(choices), increasing};
}

/// A table of keys and sub-tables. `array` makes it an array of tables ([[name]] in TOML): the
/// user may give it zero or more times, and --print-config shows one example entry.
struct SectionSpec {
  std::string name;  ///< "" for the root
  std::string help;
  bool array = false;
  std::vector<KeySpec> keys;
  std::vector<SectionSpec> sections;
};

/// A validated table. Values are always present: either given by the user or the schema's default.
class Node {
 public:
  double real(std::string_view key) const;
  std::int64_t integer(std::string_view key) const;
  bool boolean(std::string_view key) const;
  const std::string& string(std::string_view key) const;
  const Reals& reals(std::string_view key) const;
  const Strings& strings(std::string_view key) const;
  /// The value whatever its type (for a key with KeySpec::or_number).
  const Value& value(std::string_view key) const;

  const Node& section(std::string_view name) const;
  Node& section(std::string_view name);  ///< for overrides through set()
  const std::vector<Node>& array(std::string_view name) const;

  /// True when the user wrote the key (or it was overridden) rather than taking the default.
  bool given(std::string_view key) const;
  /// Replaces a value (command-line flags override the file). The type must match the schema.
  void set(std::string_view key, Value v);

  /// The file, line and dotted key of `key` (line of the table when the key took its default).
  Location where(std::string_view key) const;
  /// Throws InputError located at `key`: for checks across keys that the schema cannot express.
  [[noreturn]] void fail(std::string_view key, const std::string& problem, const std::string& got = {},
                         const std::string& expected = {}) const;

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }  ///< dotted path of this table ("" = root)

 private:
  friend class NodeBuilder;
  struct Entry {
    Value value;
    const KeySpec* spec = nullptr;
    int line = 0;
    bool given = false;
  };
  const Entry& entry(std::string_view key) const;
  template <class T>
  const T& get(std::string_view key) const;

  std::string file_;
  std::string path_;
  int line_ = 0;
  std::map<std::string, Entry, std::less<>> entries_;
  std::map<std::string, Node, std::less<>> sections_;
  std::map<std::string, std::vector<Node>, std::less<>> arrays_;
};

/// Reads and validates `file`. Throws FileError when it cannot be read, InputError for a TOML syntax
/// error, an unknown key, a wrong type, a NaN or a value out of range.
Node read_config(const SectionSpec& schema, const std::string& file);
/// Same from text; `name` stands for the file in messages.
Node parse_config(const SectionSpec& schema, std::string_view text, const std::string& name);
/// The schema's defaults, as if an empty file were read.
Node default_config(const SectionSpec& schema);
/// A fully commented TOML file with every key at its default (and one example entry of each array
/// of tables); reading it back gives default_config plus those example entries.
std::string print_config(const SectionSpec& schema);

/// Formats a value as TOML would write it.
std::string to_toml(const Value& v);
/// The closest name to `word` among `names` (edit distance ≤ max(2, length/3)), or "".
std::string closest_name(std::string_view word, const Strings& names);

/// The allowed values of a key as an error message gives them: "one of a, b", "0 to 1", ">= 0", or "".
std::string range_text(const KeySpec& k);

}  // namespace tricot::io
