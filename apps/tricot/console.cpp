#include "console.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <utility>

namespace tricot::cli {

Console::Console(bool verbose, bool quiet) : verbose_(verbose), quiet_(quiet), tty_(isatty(fileno(stderr)) != 0) {}

Console::~Console() { clear_line(); }

project::Log Console::log() {
  return project::Log(reporter(), [this](const std::string& l) { print(l); });
}

Reporter Console::reporter() {
  return Reporter{[this](const Progress& p) { on_progress(p); }, [this](const std::string& l) { on_log(l); }};
}

void Console::clear_line() {
  if (line_open_) {
    std::fputs("\n", stderr);
    line_open_ = false;
  }
}

void Console::print(const std::string& line) {
  std::lock_guard lock(mutex_);
  clear_line();
  std::fputs((line + "\n").c_str(), stdout);
  std::fflush(stdout);
}

void Console::on_log(const std::string& line) {
  if (!verbose_) return;
  std::lock_guard lock(mutex_);
  clear_line();
  std::fputs((line + "\n").c_str(), stderr);
}

void Console::line_per_step(std::string stage) {
  std::lock_guard lock(mutex_);
  per_step_stage_ = std::move(stage);
}

void Console::on_progress(const Progress& p) {
  if (quiet_) return;
  std::lock_guard lock(mutex_);
  if (!tty_ && !per_step_stage_.empty() && p.stage == per_step_stage_) {
    if (!p.detail.empty())
      std::fprintf(stderr, "%s: %s (%zu/%zu)\n", p.stage.c_str(), p.detail.c_str(), p.done, p.total);
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  if (p.stage != stage_) {
    clear_line();
    stage_ = p.stage;
    stage_start_ = now;
    last_print_ = now - std::chrono::hours(1);
  }
  const bool done = p.total > 0 && p.done >= p.total;
  const auto since = std::chrono::duration<double>(now - last_print_).count();
  if (!done && since < (tty_ ? 0.1 : 5.0)) return;
  last_print_ = now;
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  std::string line = fmt::format("{}: {}", p.stage, p.done);
  if (p.total > 0) {
    line += fmt::format("/{} ({:.0f} %)", p.total, 100.0 * double(p.done) / double(p.total));
    if (p.done > 0 && !done) line += ", ETA " + format_duration(elapsed * double(p.total - p.done) / double(p.done));
  }
  line += ", " + format_duration(elapsed);
  if (!p.detail.empty()) line += " — " + p.detail;
  if (tty_) {
    std::fputs(("\r\033[K" + line).c_str(), stderr);
    line_open_ = true;
    if (done) clear_line();
  } else {
    std::fputs((line + "\n").c_str(), stderr);
  }
  std::fflush(stderr);
}

}  // namespace tricot::cli
