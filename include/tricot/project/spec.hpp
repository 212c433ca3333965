// The project's specs: one struct per config table, whose fields are the table's TOML keys. A spec is
// read from a validated io::Node (the file's types and ranges already checked by its schema) or built
// in code, and checked by one validate() that builds the engines' options and calls their validate():
// the engines name a bad option by the same dotted key as the config ("dic.subset_size",
// "identify.epsilon"), so an Origin places the error at the key's file and line, or at the
// command-line flag that set it, without renaming it.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "tricot/core/error.hpp"
#include "tricot/io/config.hpp"

namespace tricot::project {

/// Where the keys of one table came from.
class Origin {
 public:
  /// A table built in code: an error names its dotted key alone (`path`.KEY).
  explicit Origin(std::string path = {}) : path_(std::move(path)) {}
  /// A table read from a file: an error names FILE:LINE: path.KEY.
  explicit Origin(const io::Node& table) : path_(table.path()), table_(table) {}

  /// `key` was set by a command-line flag: an error about it names `command line: FLAG`.
  void set_by_flag(const std::string& key, const std::string& flag);
  /// The file, line and dotted key of `key`, or the flag that set it.
  Location where(std::string_view key) const;
  const std::string& path() const { return path_; }
  /// Throws InputError at `key`: for checks across keys that no engine makes.
  [[noreturn]] void fail(std::string_view key, const std::string& problem, const std::string& got = {},
                         const std::string& expected = {}) const;
  /// Whether an engine's error names a key of this table (its key starts with path + ".").
  bool owns(const InputError& e) const;
  /// Rethrows an engine's error at its key of this table (owns(e) must hold).
  [[noreturn]] void rethrow(const InputError& e) const;

 private:
  std::string path_;
  std::optional<io::Node> table_;
  std::map<std::string, Location, std::less<>> flags_;
};

/// Checks `value`, set in code, against key `key` of the schema table `table` as io checks a file's
/// value (numbers finite and in [min, max], each element of a list too; a word one of the choices):
/// throws InputError at `origin`'s key naming the value and the range, in io's words. The one check of
/// a spec's keys whose range the schema holds, for a spec built in code (a file's were checked when read).
void check_key(const Origin& origin, const io::SectionSpec& table, std::string_view key, const io::Value& value);

/// The message of `e` after its key (`e.what()` is "KEY: problem (got …, expected …)" when `e` names
/// no file), to throw the same problem at another place.
std::string problem_of(const InputError& e);

}  // namespace tricot::project
