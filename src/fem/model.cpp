// Consistency checks of a test model (docs/theory.md §6).
#include "tricot/fem/model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/fem/element.hpp"

namespace tricot::fem {

std::vector<std::string> TestModel::resultant_boundaries() const {
  if (!resultants.empty()) return resultants;
  std::vector<std::string> names;
  for (const BoundaryCondition& c : conditions)
    if (std::find(names.begin(), names.end(), c.boundary) == names.end()) names.push_back(c.boundary);
  return names;
}

void TestModel::validate_conditions() const {
  const std::string who = "test '" + name + "': ";
  auto bad = [&](const std::string& key, const std::string& problem, const std::string& got = {},
                 const std::string& expected = {}) {
    throw InputError(Location{"", 0, key}, who + problem, got, expected);
  };
  if (loads.empty()) bad("test.loads", "no load steps", "[]", "at least one step");
  for (size_t k = 0; k < loads.size(); ++k) {
    if (!std::isfinite(loads[k]))
      bad("test.loads", "step " + std::to_string(k + 1) + " is not a finite number", format_number(loads[k]));
    if (k > 0 && !(loads[k] > loads[k - 1]))
      bad("test.loads", "step labels must increase strictly (step " + std::to_string(k + 1) + ")",
          format_number(loads[k]) + " after " + format_number(loads[k - 1]), "strictly increasing labels");
  }
  // The quarter's own conditions do not apply to a model of any mesh.
  if (control != GripControl::displacement || side != SideEdge::free || !guide.empty() ||
      guide_gap != 0 || guide_setting_steps != 0 || guide_tie_stiffness != 0 || guide_taper != 0 ||
      grip_tie_stiffness != 0 || grip_taper != 0 || grip_follows_guide)
    bad("test.conditions", "boundary conditions per named boundary replace the quarter model's grip and guide",
        "both", "conditions, or the quarter's grip and guide");
  for (size_t i = 0; i < conditions.size(); ++i) {
    const BoundaryCondition& c = conditions[i];
    const std::string key = "test.conditions[" + std::to_string(i) + "]";
    mesh.boundary(c.boundary, key + ".boundary");
    if (c.component != 0 && c.component != 1)
      bad(key + ".component", "not a component", std::to_string(c.component), "0 (x) or 1 (y)");
    if (!c.values.empty() && c.values.size() != loads.size())
      bad(key + ".values", "the series on boundary '" + c.boundary + "' has " + std::to_string(c.values.size()) +
              " values for " + std::to_string(loads.size()) + " steps",
          std::to_string(c.values.size()) + " values", "one per step (" + std::to_string(loads.size()) + "), or none (fixed)");
    for (size_t k = 0; k < c.values.size(); ++k)
      if (!std::isfinite(c.values[k]))
        bad(key + ".values", "step " + std::to_string(k + 1) + " is not a finite displacement", format_number(c.values[k]), "mm");
  }
  if (!force_boundary.empty()) mesh.boundary(force_boundary, "test.force_boundary");
  if (force_component != 0 && force_component != 1)
    bad("test.force_component", "not a component", std::to_string(force_component), "0 (x) or 1 (y)");
  if (!(force_scale > 0) || !std::isfinite(force_scale))
    bad("test.force_scale", "out of range", format_number(force_scale), "> 0");
  for (size_t i = 0; i < resultants.size(); ++i) mesh.boundary(resultants[i], "test.resultants");
}

void TestModel::validate() const {
  const std::string who = "test '" + name + "': ";
  auto bad = [&](const char* key, const std::string& problem, const std::string& got = {},
                 const std::string& expected = {}) {
    throw InputError(Location{"", 0, key}, who + problem, got, expected);
  };
  if (name.empty()) throw InputError(Location{"", 0, "test.name"}, "empty test name", "\"\"", "a name");
  if (!std::isfinite(material_angle)) bad("test.material_angle", "not a finite angle", format_number(material_angle), "degrees");

  // Mesh: non-empty, consistent connectivity, four edges, no element inverted in the reference state.
  const int n = mesh.nodes();
  if (n == 0 || mesh.elements() == 0)
    bad("test.mesh", "empty mesh", std::to_string(n) + " nodes, " + std::to_string(mesh.elements()) + " elements",
        "at least one element");
  if (!mesh.X.allFinite()) bad("test.mesh", "non-finite node coordinates");
  const int per = nodes_per_element(mesh.type);
  for (int e = 0; e < mesh.elements(); ++e)
    for (int a = 0; a < per; ++a)
      if (mesh.connectivity[e][a] < 0 || mesh.connectivity[e][a] >= n)
        bad("test.mesh", "element " + std::to_string(e) + " refers to a missing node",
            std::to_string(mesh.connectivity[e][a]), "0 to " + std::to_string(n - 1));
  const std::pair<const char*, const std::vector<int>*> edges[] = {
      {"left", &mesh.left}, {"bottom", &mesh.bottom}, {"top", &mesh.top}, {"right", &mesh.right}};
  for (const auto& [edge, set] : edges) {
    if (has_conditions()) break;  // a model of any mesh names its boundaries instead
    if (set->empty()) bad("test.mesh", std::string("no nodes on the ") + edge + " edge");
    for (int v : *set)
      if (v < 0 || v >= n) bad("test.mesh", std::string("bad node on the ") + edge + " edge", std::to_string(v));
  }
  for (int e = 0; e < mesh.elements(); ++e) {
    const double det = element_geometry(mesh, e).min_detJ0;
    if (!(det > 0))
      bad("test.mesh", "element " + std::to_string(e) + " is inverted or degenerate in the reference mesh",
          "det(dX/dxi) = " + format_number(det), "> 0");
  }

  if (has_conditions()) {
    validate_conditions();
    return;
  }

  // Steps: strictly increasing from > 0 under force control; under displacement control any finite
  // grip path (a lab record's holds, relaxation and unloading: issue 29; the solver's predictor
  // extrapolates along the path only where the load keeps its direction).
  if (loads.empty()) bad("test.loads", "no load steps", "[]", "at least one step");
  for (size_t k = 0; k < loads.size(); ++k) {
    const double prev = k == 0 ? 0.0 : loads[k - 1];
    if (!std::isfinite(loads[k]))
      bad("test.loads", "step " + std::to_string(k + 1) + " is not a finite number", format_number(loads[k]));
    if (control == GripControl::force && !(loads[k] > prev))
      bad("test.loads",
          k == 0 ? "the first load must be > 0"
                 : "loads must increase strictly (step " + std::to_string(k + 1) + " goes backwards)",
          format_number(loads[k]) + (k == 0 ? "" : " after " + format_number(prev)), "strictly increasing values > 0 (force control; displacement control takes any path)");
  }

  // Guide: one value, or one per step; only with a guided side edge.
  if (side == SideEdge::guide) {
    if (guide.size() != 1 && guide.size() != loads.size())
      bad("test.guide", "a guide needs one value or one per step", std::to_string(guide.size()) + " values",
          "1 or " + std::to_string(loads.size()));
    for (double c : guide)
      if (!std::isfinite(c)) bad("test.guide", "not a finite displacement", format_number(c), "mm");
  } else if (!guide.empty()) {
    bad("test.guide", "guide values given but the side edge is free", std::to_string(guide.size()) + " values",
        "none (or side = guide)");
  }
  const double H = mesh.X.row(1).maxCoeff();
  if (!std::isfinite(guide_gap) || guide_gap < 0 || !(guide_gap < H))
    bad("test.guide_gap", "out of range", format_number(guide_gap), ">= 0 and < the half height " + format_number(H) + " mm");
  if (guide_gap > 0 && side != SideEdge::guide)
    bad("test.guide_gap", "a guide gap needs a guide (side = guide)", format_number(guide_gap), "0");
  if (guide_setting_steps < 0 || guide_setting_steps > 1000)
    bad("test.guide_setting_steps", "out of range", std::to_string(guide_setting_steps), "0 to 1000");
  if (guide_setting_steps > 0 && (side != SideEdge::guide || guide.size() != 1))
    bad("test.guide_setting_steps", "setting the transverse dimension first needs a guide with one value",
        std::to_string(guide_setting_steps), "0, or side = guide with one guide value");
  if (!std::isfinite(guide_tie_stiffness) || guide_tie_stiffness < 0)
    bad("test.guide_tie_stiffness", "out of range", format_number(guide_tie_stiffness), ">= 0 N/mm per mm");
  if (guide_tie_stiffness > 0 && side != SideEdge::guide)
    bad("test.guide_tie_stiffness", "ties need a guide (side = guide)", format_number(guide_tie_stiffness), "0");
  if (!std::isfinite(guide_taper) || guide_taper < 0 || !(guide_taper < H - guide_gap) ||
      (guide_taper > 0 && !(guide_tie_stiffness > 0)))
    bad("test.guide_taper", "out of range (a taper needs ties)", format_number(guide_taper),
        ">= 0 and < the guided length " + format_number(H - guide_gap) + " mm, with guide_tie_stiffness > 0");
  const double W = mesh.X.row(0).maxCoeff();
  if (!std::isfinite(grip_tie_stiffness) || grip_tie_stiffness < 0 || (grip_tie_stiffness > 0 && !grip_holds_x))
    bad("test.grip_tie_stiffness", "out of range (clip ties need grip_holds_x)", format_number(grip_tie_stiffness),
        ">= 0 N/mm per mm");
  if (!std::isfinite(grip_taper) || grip_taper < 0 || !(grip_taper < W) || (grip_taper > 0 && !(grip_tie_stiffness > 0)))
    bad("test.grip_taper", "out of range (a taper needs clip ties)", format_number(grip_taper),
        ">= 0 and < the half width " + format_number(W) + " mm, with grip_tie_stiffness > 0");
  if (grip_follows_guide && (side != SideEdge::guide || !grip_holds_x))
    bad("test.grip_follows_guide", "a grip that follows the guide needs a guide and a clamp (grip_holds_x)", "true",
        "false, or side = guide with grip_holds_x = true");
}

}  // namespace tricot::fem
