// The files an identification writes besides its checkpoint (identification.cpp). Private to
// src/project.
#pragma once

#include <filesystem>

#include "json.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/project/identification.hpp"

namespace tricot::project {

/// DIR/result.json (DESIGN.md keys, then the uncertainty, the data groups and the truth's errors).
json result_json(const IdentifyOutcome& o, const ident::Objective& objective, bool resumed);
/// result.json's "eq9" (THEORY §9, paper Table 5): {"course": {"whole", "practical", "points_whole",
/// "points_practical"}, "wale": {…}, "practical": {"course": [min, max], "wale": [min, max]}}, the
/// identified law against the experimental points; a force without points is null.
json eq9_json(const SurfacePoints& points, const fem::Law& law, const ident::StrainDomain& practical);
/// DIR/eq9_<force>.csv (eC, eW, force_exp, force_id, relative_error, practical per point),
/// DIR/eq9_surface_<force>.csv (the identified surface on a grid over the points' range) and, with
/// `plots`, DIR/plots/eq9_<force>.png: the surface with the experimental points (paper Figs 11–14)
/// and the error map with the practical domain outlined (Figs 15–16).
void write_eq9(const std::filesystem::path& dir, const SurfacePoints& points, const fem::Law& law,
               const ident::StrainDomain& practical, bool plots, const Log& log);
/// result.json's "identifiability" (ident::identifiability at the answer, rows grouped by test):
/// {"relative_std_error": {name: …}, "pinned": {name: bool}, "least_identifiable": {name: …},
/// "smallest_eigenvalue", "largest_eigenvalue", "tests": {test: {"trace_share", "weak_direction_share"}}};
/// null when the model cannot give ∂r/∂J there.
json identifiability_json(const ident::Objective& objective, const ident::IdentifyResult& r,
                          ident::IdentifiabilityOptions options);
/// DIR/history.csv: iteration, objective, one column per coefficient.
void write_history(const std::filesystem::path& file, const ident::IdentifyResult& r);
/// DIR/plots/history.png: f and every coefficient (over the truth or the identified value) per iteration.
void plot_history(const std::filesystem::path& dir, const IdentifyOutcome& o, const Log& log);
/// DIR/fit_<test>.csv and DIR/plots/fit_<test>.png: the identified model against the edge data.
void write_fit(const std::filesystem::path& dir, const ident::Objective& objective, const ident::IdentifyResult& r,
               const fem::SolveOptions& solver, bool plots, const Log& log);

}  // namespace tricot::project
