// How a pipeline reports: the engines' progress callbacks and the lines of its summary. The library
// never prints (the library never prints): the CLI's console (apps/tricot/console.hpp) decides how both are shown; a
// default Log drops them.
#pragma once

#include <functional>
#include <string>

#include "tricot/core/format.hpp"
#include "tricot/core/progress.hpp"

namespace tricot::project {

class Log {
 public:
  Log() = default;
  /// `progress` receives the engines' reports; `line` receives each summary line (results, tables).
  Log(Reporter progress, std::function<void(const std::string&)> line)
      : reporter_(std::move(progress)), line_(std::move(line)) {}
  const Reporter& reporter() const { return reporter_; }
  /// One line of a pipeline's summary (no trailing newline).
  void print(const std::string& line) const {
    if (line_) line_(line);
  }

 private:
  Reporter reporter_;
  std::function<void(const std::string&)> line_;
};

using tricot::format_duration;

}  // namespace tricot::project
