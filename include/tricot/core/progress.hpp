// The library never prints (the library never prints): long work reports through these callbacks and the CLI decides
// how to show them (progress bar with ETA, Newton tables, ...).
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace tricot {

/// One progress report: `done` of `total` units of `stage` finished. `detail` is a short free text
/// (e.g. "step 12/35, 3 Newton iterations").
struct Progress {
  std::string stage;
  std::size_t done = 0;
  std::size_t total = 0;
  std::string detail;
};

/// Callbacks handed to long-running algorithms. Empty functions are allowed and mean "ignore".
struct Reporter {
  std::function<void(const Progress&)> progress;
  std::function<void(const std::string&)> log;  ///< one line, no trailing newline

  void report(const Progress& p) const {
    if (progress) progress(p);
  }
  void info(const std::string& line) const {
    if (log) log(line);
  }
};

}  // namespace tricot
