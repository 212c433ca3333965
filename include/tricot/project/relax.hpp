// tricot relax LOG -o DIR (issue 11, paper §3.1.1): the hold of a relaxation test fitted by a Prony
// series of one to three exponentials (lab/relaxation.hpp), and whether a test of a given duration is
// quasi-static against it. Writes
//   DIR/relax.json   hold, every fit (terms, F∞, rms, BIC), the chosen one, the quasi-static verdict
//   DIR/relax.csv    time, force (tare removed), fit_1 .. fit_m over the hold
//   DIR/relax.png    the force and the fits against time since the hold began (gnuplot)
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "tricot/lab/relaxation.hpp"
#include "tricot/project/log.hpp"

namespace tricot::project {

struct RelaxSpec {
  std::string log;  ///< the relaxation log (CSV or tab-separated, as io::read_log reads)
  std::string time_column = "time";
  std::string force_column = "force";
  std::string crosshead_column;  ///< "" = none: the hold begins at the force's peak
  lab::RelaxationOptions options;
  std::optional<double> duration_s;  ///< quasi-static verdict for a monotonic test of this duration
};

struct RelaxRun {
  lab::RelaxationResult result;
  std::optional<lab::QuasiStatic> verdict;
};

/// Reads the log, fits, writes DIR. InputError / FileError for a bad log (FILE:LINE: COLUMN).
RelaxRun run_relax(const RelaxSpec& spec, const std::filesystem::path& dir, const Log& log);

}  // namespace tricot::project
