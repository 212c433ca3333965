// How the CLI shows the library's progress and log callbacks: a progress line with an ETA on stderr
// (rewritten in place on a terminal, one line every few seconds otherwise), log lines when verbose.
#pragma once

#include <chrono>
#include <mutex>
#include <string>

#include "tricot/core/progress.hpp"

namespace tricot::cli {

class Console {
 public:
  explicit Console(bool verbose = false, bool quiet = false);
  ~Console();
  /// A Reporter whose callbacks print here. The Console must outlive it.
  Reporter reporter();
  /// Prints a line to stdout (results, tables), finishing any progress line first.
  void print(const std::string& line);

 private:
  void on_progress(const Progress& p);
  void on_log(const std::string& line);
  void clear_line();

  bool verbose_, quiet_, tty_;
  std::mutex mutex_;
  std::string stage_;
  std::chrono::steady_clock::time_point stage_start_, last_print_;
  bool line_open_ = false;
};

/// "1 h 02 min", "3 min 20 s", "12.3 s", "85 ms".
std::string format_duration(double seconds);

}  // namespace tricot::cli
