// The files an identification writes besides its checkpoint (identification.cpp). Private to
// src/project.
#pragma once

#include <cmath>
#include <filesystem>
#include <string>

#include "output/json.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/project/identification.hpp"

namespace tricot::project {

/// DIR/result.json (docs/design.md keys, then the uncertainty, the data groups and the truth's errors).
json result_json(const IdentifyOutcome& o, const ident::Objective& objective, bool resumed);
/// χ²/dof of the data at J* (ScaledResiduals::chi_square over N − n); NaN without measurement σ on
/// every group, or without the residuals at J*.
double chi2_per_dof(const ident::Objective& objective, const ident::IdentifyResult& r);
/// result.json's "eq9" (docs/theory.md §9, paper Table 5): {"course": {"computed", "whole", "practical",
/// "points_whole", "points_practical", "held_levels"}, "wale": {…}, "practical": {"course": [min, max],
/// "wale": [min, max]}}, the identified law against the experimental points; a force without points is
/// null; a surface whose points probe it at fewer than `min_held_levels` transverse levels has
/// "computed": false, null errors and a "reason".
json eq9_json(const SurfacePoints& points, const fem::Law& law, const ident::StrainDomain& practical,
              int min_held_levels);
/// DIR/eq9_<force>.csv (eC, eW, force_exp, force_id, relative_error, practical per point),
/// DIR/eq9_surface_<force>.csv (the identified surface on a grid over the points' range) and, with
/// `plots`, DIR/plots/eq9_<force>.png: the surface with the experimental points (paper Figs 11–14)
/// and the error map with the practical domain outlined (Figs 15–16).
void write_eq9(const std::filesystem::path& dir, const SurfacePoints& points, const fem::Law& law,
               const ident::StrainDomain& practical, bool plots, const Log& log);
/// result.json's "identifiability" (ident::identifiability at the answer, rows grouped by test):
/// {"relative_std_error": {name: …}, "pinned": {name: bool}, "least_identifiable": {name: …},
/// "smallest_eigenvalue", "largest_eigenvalue", "tests": {test: {"trace_share", "weak_direction_share"}}};
/// null when `at_answer` (the objective's evaluation at the answer, with ∂r/∂J) is not usable.
json identifiability_json(const ident::Objective& objective, const ident::IdentifyResult& r,
                          const ident::Evaluation& at_answer, ident::IdentifiabilityOptions options);
/// result.json's "design" ([design]; ident::suggest_test): {"criterion", "worst_relative_std_error_now",
/// "best", "candidates": [{"name", "pull", "transverse_strain", "score", "worst_relative_std_error_with"}
/// or {…, "failed": message}]}. Each candidate is the first rig test of its pull held at another strain,
/// measured at that test's field points from the identified law, its rows scaled as the data's. Null
/// when `at_answer` is not usable or no candidate could be simulated.
json design_json(const IdentificationSpec& spec, const Project& P, const ident::IdentifyResult& r,
                 const ident::Evaluation& at_answer, const Log& log);
/// DIR/history.csv: iteration, objective, one column per coefficient.
void write_history(const std::filesystem::path& file, const ident::IdentifyResult& r);
/// DIR/plots/history.png: f and every coefficient (over the truth or the identified value) per iteration.
void plot_history(const std::filesystem::path& dir, const IdentifyOutcome& o, const Log& log);
/// DIR/fit_<test>.csv and DIR/plots/fit_<test>.png: the identified model against the edge data (the
/// objective's simulations at the answer: Objective::simulations).
/// DIR/fit_field_<test>.csv and plots/fit_field_<test>.png (the residual map) for each test with a
/// cumulative field; returns each test's fit: the RMS |model − measured| of its points and its force RMS.
struct TestFit {
  std::string name;
  double points_rms_mm = std::nan("");  ///< over every point and step; NaN: no (cumulative) field
  double force_rms_N = std::nan("");    ///< NaN: no measured force
  double force_peak_N = std::nan("");
  /// A tension-field law (docs/theory/fabric.md §8): the area fractions wrinkled and slack at the last
  /// step; NaN otherwise.
  double wrinkled_area = std::nan(""), slack_area = std::nan("");
};
/// Also, for a tension-field law, DIR/wrinkles_<test>.csv (per element at the last step: its reference
/// centroid, wrinkled and slack area fractions, wrinkle direction) and plots/wrinkles_<test>.png.
std::vector<TestFit> write_fit_field(const std::filesystem::path& dir, const ident::Objective& objective,
                                     const ident::IdentifyResult& r, bool plots, const Log& log);
void write_fit(const std::filesystem::path& dir, const ident::Objective& objective, const ident::IdentifyResult& r,
               bool plots, const Log& log);

}  // namespace tricot::project
