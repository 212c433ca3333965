// How the CLI shows the library's progress and log callbacks: a progress line with an ETA on stderr
// (rewritten in place on a terminal, one line every few seconds otherwise), log lines when verbose.
#pragma once

#include <chrono>
#include <mutex>
#include <string>

#include "tricot/core/progress.hpp"
#include "tricot/project/log.hpp"

namespace tricot::cli {

class Console {
 public:
  explicit Console(bool verbose = false, bool quiet = false);
  ~Console();
  /// A Reporter whose callbacks print here. The Console must outlive it.
  Reporter reporter();
  /// A project::Log whose lines and progress go here. The Console must outlive it.
  project::Log log();
  /// Prints a line to stdout (results, tables), finishing any progress line first.
  void print(const std::string& line);
  /// Off a terminal (a log file, a batch job), each progress report of `stage` that carries a detail
  /// gets a line of its own, "stage: detail (done/total)", instead of one line every few seconds:
  /// for a long job whose every step is worth a line (tricot dic's frames). On a terminal, unchanged.
  void line_per_step(std::string stage);

 private:
  void on_progress(const Progress& p);
  void on_log(const std::string& line);
  void clear_line();

  bool verbose_, quiet_, tty_;
  std::mutex mutex_;
  std::string stage_, per_step_stage_;
  std::chrono::steady_clock::time_point stage_start_, last_print_;
  bool line_open_ = false;
};

using project::format_duration;

}  // namespace tricot::cli
