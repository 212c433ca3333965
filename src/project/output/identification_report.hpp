// DIR/report.html and DIR/report.json of `tricot identify` (report.hpp's document, filled from one
// identification). Private to src/project.
#pragma once

#include <filesystem>

#include "tricot/io/config.hpp"
#include "tricot/project/identification.hpp"
#include "tricot/project/report.hpp"

namespace tricot::project {

/// The identification's report: inputs and settings, LM history, coefficients with standard errors
/// and 95 % intervals, correlation heat map, local identifiability, fits, wall time. Figures are the
/// PNGs under `out`/plots (a note stands in for those not drawn).
report::Document identification_report(const IdentificationSpec& spec, const Project& project,
                                       const IdentifyOutcome& outcome, const std::filesystem::path& out,
                                       double wall_seconds);

/// Builds identification_report and writes `out`/report.html and report.json.
void write_identification_report(const IdentificationSpec& spec, const Project& project, const IdentifyOutcome& outcome,
                                 const std::filesystem::path& out, double wall_seconds);

}  // namespace tricot::project
