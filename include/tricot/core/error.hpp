// Errors and exit codes (docs/design.md, "Exit codes").
//   - broken invariant  -> assert (debug only)
//   - bad input         -> InputError (exit 2) or FileError (exit 3), with file, line and key
//   - non-convergence   -> a status in the result, never an exception (exit 4 from the CLI)
#pragma once

#include <stdexcept>
#include <string>

namespace tricot {

/// Process exit codes of the `tricot` program (docs/design.md).
enum class ExitCode : int {
  ok = 0,
  usage = 2,          ///< bad command line, config or input value
  input_missing = 3,  ///< an input file is missing or unreadable
  not_converged = 4,  ///< the run finished but did not converge
};

/// Where a bad value came from. Every field is optional; the message names those that are set.
struct Location {
  std::string file;  ///< path as the user gave it
  int line = 0;      ///< 1-based, 0 = unknown
  std::string key;   ///< dotted config key or CSV column, "" = none
};

/// Bad input, config or value. `what()` is the one-line message the CLI prints after "tricot: error: ":
/// `FILE:LINE: KEY: what is wrong (got VALUE, expected RANGE)`.
class InputError : public std::runtime_error {
 public:
  InputError(Location where, const std::string& problem, const std::string& got = {}, const std::string& expected = {});
  const Location& where() const { return where_; }
  const std::string& problem() const { return problem_; }
  virtual ExitCode exit_code() const { return ExitCode::usage; }

 private:
  Location where_;
  std::string problem_;
};

/// An input file is missing, unreadable or not what it should be (an image that cannot be decoded).
class FileError : public InputError {
 public:
  using InputError::InputError;
  ExitCode exit_code() const override { return ExitCode::input_missing; }
};

/// Formats `FILE:LINE: KEY: problem (got G, expected E)`, leaving out what is empty.
std::string format_error(const Location& where, const std::string& problem, const std::string& got,
                         const std::string& expected);

/// How messages show a number: 6 significant digits (`%.6g`), "nan"/"inf" spelled out.
std::string format_number(double v);

}  // namespace tricot
