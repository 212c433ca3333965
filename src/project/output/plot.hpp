// The plots: every PNG tricot draws is a gnuplot script run here, after one header (the pngcairo
// terminal, the output file, data read as CSV). A plot is a convenience, never a reason to fail a run:
// when gnuplot is missing or fails, the run goes on and its log says why.
#pragma once

#include <filesystem>
#include <string>

#include "tricot/project/log.hpp"

namespace tricot::project {

/// A PNG that gnuplot draws.
struct Figure {
  std::filesystem::path png;
  int width = 0, height = 0;  ///< pixels
  int font_size = 11;         ///< points
  bool enhanced = true;       ///< false: gnuplot's `noenhanced`, text shown as written (a test named a_b keeps its _)
  std::string name = "plot";  ///< what the log calls it when it cannot be drawn: "  (no NAME: why)"
};

/// Draws `figure`: its header, then `body` (gnuplot commands; data paths through io::gnuplot_quote).
/// When gnuplot is missing or fails, prints "  (no NAME: why)" to `log`.
void plot(const Figure& figure, const std::string& body, const Log& log);

}  // namespace tricot::project
