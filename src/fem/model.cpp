// Consistency checks of a test model (docs/theory.md §6).
#include "tricot/fem/model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
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

namespace {

// The element sides whose nodes all lie in `in`, each once: corners a, b and the mid-side node m of a
// quadratic side (−1 on a linear one).
struct Side {
  int a, m, b;
};
std::vector<Side> boundary_sides(const Mesh& mesh, const std::vector<char>& in) {
  const int k = corners(mesh.type);
  const bool quadratic = nodes_per_element(mesh.type) > k;
  std::set<std::pair<int, int>> seen;
  std::vector<Side> sides;
  for (const auto& c : mesh.connectivity)
    for (int s = 0; s < k; ++s) {
      const int a = c[s], b = c[(s + 1) % k], m = quadratic ? c[k + s] : -1;
      if (!in[a] || !in[b] || (quadratic && !in[m])) continue;
      if (seen.insert({std::min(a, b), std::max(a, b)}).second) sides.push_back({a, m, b});
    }
  return sides;
}

// The arc length s of each node of `sides` along them, from the end farther from `end`, and s at the
// point closest to `end`; empty when the sides are not one open line.
std::map<int, double> arc_lengths(const Mesh& mesh, const std::vector<Side>& sides, const Vec2& end, double& s_end) {
  std::map<int, std::vector<int>> next;
  for (const Side& d : sides) {
    const int m = d.m >= 0 ? d.m : d.b;
    next[d.a].push_back(m), next[m].push_back(d.a);
    if (d.m >= 0) next[d.m].push_back(d.b), next[d.b].push_back(d.m);
  }
  int start = -1;
  for (const auto& [n, v] : next)
    if (v.size() == 1) {
      start = n;
      break;
    }
  std::vector<int> chain;
  for (int previous = -1, n = start; n >= 0 && chain.size() <= next.size();) {
    chain.push_back(n);
    const std::vector<int>& v = next[n];
    if (v.size() > 2) break;
    const int from = previous;
    previous = n, n = -1;
    for (int m : v)
      if (m != from) n = m;
  }
  bool line = !chain.empty() && chain.size() == next.size();
  for (const auto& [n, v] : next) line = line && v.size() <= 2;
  if (!line) return {};
  std::vector<double> s(chain.size(), 0.0);
  for (size_t k = 1; k < chain.size(); ++k) s[k] = s[k - 1] + (mesh.X.col(chain[k]) - mesh.X.col(chain[k - 1])).norm();
  double best = INFINITY;
  for (size_t k = 0; k + 1 < chain.size(); ++k) {
    const Vec2 a = mesh.X.col(chain[k]), d = mesh.X.col(chain[k + 1]) - a;
    const double t = std::clamp((end - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const double dist = (a + t * d - end).norm();
    if (dist < best) best = dist, s_end = s[k] + t * (s[k + 1] - s[k]);
  }
  const double total = s.back();
  const bool reverse = s_end < total - s_end;  // measure from the other end
  if (reverse) s_end = total - s_end;
  std::map<int, double> out;
  for (size_t k = 0; k < chain.size(); ++k) out[chain[k]] = reverse ? total - s[k] : s[k];
  return out;
}

}  // namespace

std::vector<std::pair<int, double>> TestModel::tie_stiffness(size_t i) const {
  const BoundaryCondition& c = conditions.at(i);
  const std::string key = "test.conditions[" + std::to_string(i) + "]";
  const std::vector<int>& nodes = mesh.boundary(c.boundary, key + ".boundary");
  std::vector<char> in(mesh.nodes(), 0);
  for (int n : nodes) in[n] = 1;
  const std::vector<Side> sides = boundary_sides(mesh, in);
  if (sides.empty())
    throw InputError(Location{"", 0, key + ".tie"},
                     "test '" + name + "': the boundary '" + c.boundary + "' has no length to tie (points only)",
                     format_number(c.tie), "a boundary along element sides");
  // Arc length along the line, when the tie ends (else the whole boundary is tied: s = 0, s_end = ∞).
  double s_end = INFINITY;
  std::map<int, double> s;
  if (c.tie_end) {
    s = arc_lengths(mesh, sides, *c.tie_end, s_end);
    if (s.empty())
      throw InputError(
          Location{"", 0, key + ".tie_end"},
          "test '" + name + "': a tie that ends needs the boundary '" + c.boundary + "' to be one open line",
          "[" + format_number((*c.tie_end)(0)) + ", " + format_number((*c.tie_end)(1)) + "]",
          "a boundary without branches or loops, or no tie_end");
  }
  auto at = [&](int n) { return s.empty() ? 0.0 : s.at(n); };
  auto taper = [&](double x) { return c.tie_taper > 0 ? std::clamp((s_end - x) / c.tie_taper, 0.0, 1.0) : 1.0; };
  std::map<int, double> share;  // N/mm
  auto length = [&](int a, int b) { return (mesh.X.col(a) - mesh.X.col(b)).norm(); };
  for (const Side& d : sides) {
    if (!c.tie_consistent) {
      // Half of each node-to-node segment's tied part to each of its nodes before the end, the taper at
      // the node (the built-in rig's rule, docs/theory.md §6).
      const std::array<int, 3> p = {d.a, d.m >= 0 ? d.m : d.b, d.b};
      for (int k = 0; k < (d.m >= 0 ? 2 : 1); ++k) {
        int lo = p[k], hi = p[k + 1];
        if (at(lo) > at(hi)) std::swap(lo, hi);
        const double L = length(lo, hi), tied = s.empty() ? L : std::max(std::min(at(hi), s_end) - at(lo), 0.0);
        if (at(lo) <= s_end + 1e-9 * L) share[lo] += c.tie * 0.5 * tied * taper(at(lo));
        if (at(hi) <= s_end + 1e-9 * L) share[hi] += c.tie * 0.5 * L * taper(at(hi));
      }
      continue;
    }
    // Consistent: ∫ tie · taper(s) · N_i ds over the side's tied part, the side mapped linearly on
    // ξ ∈ [−1, 1] (3 Gauss points per part: exact for a straight side without taper).
    int first = d.a, last = d.b;
    if (at(first) > at(last)) std::swap(first, last);
    const double L = d.m >= 0 ? length(d.a, d.m) + length(d.m, d.b) : length(d.a, d.b);
    const double s0 = at(first), s1 = s.empty() ? L : at(last);
    const double xi_end = std::min(1.0, -1 + 2 * (s_end - s0) / (s1 - s0));
    if (!(xi_end > -1)) continue;
    static const double g[3] = {-0.7745966692414834, 0.0, 0.7745966692414834}, w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    for (int q = 0; q < 3; ++q) {
      const double xi = -1 + 0.5 * (xi_end + 1) * (g[q] + 1), dxi = 0.5 * (xi_end + 1) * w[q];
      const double f = c.tie * taper(s0 + 0.5 * (xi + 1) * (s1 - s0)) * 0.5 * L * dxi;
      const double N_first = d.m >= 0 ? 0.5 * xi * (xi - 1) : 0.5 * (1 - xi),
                   N_last = d.m >= 0 ? 0.5 * xi * (xi + 1) : 0.5 * (1 + xi);
      share[first] += f * N_first, share[last] += f * N_last;
      if (d.m >= 0) share[d.m] += f * (1 - xi * xi);
    }
  }
  std::vector<std::pair<int, double>> out;
  for (const auto& [n, k] : share)
    if (k > 0 || at(n) <= s_end) out.emplace_back(n, k);
  return out;
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
  if (control != GripControl::displacement || side != SideEdge::free || !guide.empty() || guide_gap != 0 ||
      guide_setting_steps != 0 || guide_tie_stiffness != 0 || guide_taper != 0 || grip_tie_stiffness != 0 ||
      grip_taper != 0 || grip_follows_guide)
    bad("test.conditions", "boundary conditions per named boundary replace the quarter model's grip and guide", "both",
        "conditions, or the quarter's grip and guide");
  for (size_t i = 0; i < conditions.size(); ++i) {
    const BoundaryCondition& c = conditions[i];
    const std::string key = "test.conditions[" + std::to_string(i) + "]";
    mesh.boundary(c.boundary, key + ".boundary");
    if (c.component != 0 && c.component != 1)
      bad(key + ".component", "not a component", std::to_string(c.component), "0 (x) or 1 (y)");
    if (!c.values.empty() && c.values.size() != loads.size())
      bad(key + ".values",
          "the series on boundary '" + c.boundary + "' has " + std::to_string(c.values.size()) + " values for " +
              std::to_string(loads.size()) + " steps",
          std::to_string(c.values.size()) + " values",
          "one per step (" + std::to_string(loads.size()) + "), or none (fixed)");
    for (size_t k = 0; k < c.values.size(); ++k)
      if (!std::isfinite(c.values[k]))
        bad(key + ".values", "step " + std::to_string(k + 1) + " is not a finite displacement",
            format_number(c.values[k]), "mm");
    if (c.proportional && c.values.empty())
      bad(key + ".proportional", "a proportional condition needs its values", "true", "values per step (mm per mm)");
    if (!(c.tie >= 0) || !std::isfinite(c.tie))
      bad(key + ".tie", "out of range", format_number(c.tie), ">= 0 N/mm per mm");
    if (c.tie == 0 && (c.tie_end || c.tie_taper != 0))
      bad(key + ".tie", "tie_end and tie_taper need a tie", "0", "> 0 N/mm per mm");
    if (!(c.tie_taper >= 0) || !std::isfinite(c.tie_taper))
      bad(key + ".tie_taper", "out of range", format_number(c.tie_taper), ">= 0 mm");
    if (c.tie_taper > 0 && !c.tie_end)
      bad(key + ".tie_taper", "a taper needs the tie's end", format_number(c.tie_taper), "tie_end");
    if (c.tie_end && !c.tie_end->allFinite()) bad(key + ".tie_end", "not a finite point", "", "[x, y] in mm");
    if (c.tie > 0) tie_stiffness(i);
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
  if (!std::isfinite(material_angle))
    bad("test.material_angle", "not a finite angle", format_number(material_angle), "degrees");

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
          format_number(loads[k]) + (k == 0 ? "" : " after " + format_number(prev)),
          "strictly increasing values > 0 (force control; displacement control takes any path)");
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
    bad("test.guide_gap", "out of range", format_number(guide_gap),
        ">= 0 and < the half height " + format_number(H) + " mm");
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
  if (!std::isfinite(grip_taper) || grip_taper < 0 || !(grip_taper < W) ||
      (grip_taper > 0 && !(grip_tie_stiffness > 0)))
    bad("test.grip_taper", "out of range (a taper needs clip ties)", format_number(grip_taper),
        ">= 0 and < the half width " + format_number(W) + " mm, with grip_tie_stiffness > 0");
  if (grip_follows_guide && (side != SideEdge::guide || !grip_holds_x))
    bad("test.grip_follows_guide", "a grip that follows the guide needs a guide and a clamp (grip_holds_x)", "true",
        "false, or side = guide with grip_holds_x = true");
}

}  // namespace tricot::fem
