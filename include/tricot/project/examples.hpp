// The files of examples/ that the demos run, built into tricot at build time (cmake/TricotEmbed.cmake;
// src/project/CMakeLists.txt lists them), so that an installed tricot needs no source tree. A demo
// reads them with the verbs' schemas; a variant of one (another noise level, other data weights) is
// the file with some values changed (with_value), not a second copy.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "tricot/io/config.hpp"

namespace tricot::project {

/// One built-in file: its path under examples/ and its bytes.
struct ExampleFile {
  std::string_view path;  ///< e.g. "uniaxial-mooney/project.toml"
  std::string_view text;
};

/// Every built-in file.
std::span<const ExampleFile> example_files();

/// The text of examples/`path`. Throws std::logic_error when it is not built in.
std::string_view example_file(std::string_view path);

/// `toml` with the value of `key` in its table [`table`] ("" = before the first table), a value on
/// one line, replaced by `value`, the rest of the line (its comment) kept. The first such key counts (in an array of
/// tables, the first entry's). Throws std::logic_error when there is none.
std::string with_value(std::string_view toml, std::string_view table, std::string_view key, const io::Value& value);

}  // namespace tricot::project
