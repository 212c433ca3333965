// Specs from Python (issue 33): a dict becomes TOML text and goes through the same config reader as a
// file (io::parse_config with the verb's schema), so defaults, ranges and error messages are the CLI's;
// a str or os.PathLike names a TOML file (io::read_config). And the Python exception classes, one per
// exit-code class of the CLI (docs/design.md, "Exit codes"), carrying the CLI's one-line message.
#pragma once

#include <pybind11/pybind11.h>

#include <filesystem>
#include <string>

#include "tricot/io/config.hpp"

namespace tricot::python {

namespace py = pybind11;

/// A verb's config, read and validated by its schema.
struct LoadedSpec {
  io::Node root;
  /// The folder relative paths are taken from: the file's folder, or for a dict `base` (default the
  /// current folder).
  std::filesystem::path base;
  std::string name;  ///< the file as given, or "<dict>" (what error messages name)
};

/// The TOML text of a dict: tables for dicts, arrays of tables for lists of dicts, os.PathLike as
/// strings, NumPy arrays and scalars through tolist(). Throws ConfigError for a value TOML cannot hold.
std::string to_toml(const py::handle& spec);

/// Reads `spec` (a dict, a TOML path, or None for the schema's defaults) with `schema`. A dict is named
/// "<dict>" in messages (BASE/<dict> with a `base`), and its relative paths are taken from `base`
/// (None = the current folder).
LoadedSpec load_spec(const py::handle& spec, const io::SectionSpec& schema, const py::handle& base);

/// Refuses an output folder before any work, as the CLI's -o (empty, a file, or under a file).
void check_out_dir(const std::string& dir);

/// The exception classes (tricot.Error and its subclasses) and the translator of tricot's C++ errors.
void register_errors(py::module_& m);

/// Raises tricot.NotConvergedError (exit code 4) with `message`, its `result` attribute set.
[[noreturn]] void raise_not_converged(const std::string& message, const py::object& result);

/// A path argument (str or os.PathLike) as a string.
std::string path_string(const py::handle& p);

}  // namespace tricot::python
