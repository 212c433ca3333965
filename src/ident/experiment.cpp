// Checks of measured data (docs/theory.md §2): everything the objective relies on, before any FE run.
#include "tricot/ident/experiment.hpp"

#include <cassert>
#include <cmath>
#include <set>
#include <string>

#include "tricot/core/error.hpp"

namespace tricot::ident {

const char* to_string(FieldKind k) { return k == FieldKind::cumulative ? "cumulative" : "incremental"; }

void TestData::validate() const {
  const std::string key = "experiment." + (name.empty() ? std::string("?") : name) + ".";
  auto fail = [&](const std::string& field, const std::string& problem, const std::string& got = {},
                  const std::string& expected = {}) {
    throw InputError(Location{source, 0, key + field}, problem, got, expected);
  };
  if (name.empty()) fail("name", "a test needs a name");
  const int n = steps();
  if (n == 0) fail("loads", "no steps");
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(loads[k]))
      fail("loads", "non-finite load at step " + std::to_string(k), format_number(loads[k]));
    // Any finite path: a lab record's holds and unloading (issue 29); the model's control says
    // whether it must increase (fem::TestModel::validate).
  }
  auto per_step = [&](const std::vector<double>& v, const char* field) {
    if (v.empty()) return;
    if (static_cast<int>(v.size()) != n)
      fail(field, "one value per step", std::to_string(v.size()) + " values", std::to_string(n));
    for (int k = 0; k < n; ++k)
      if (!std::isfinite(v[k])) fail(field, "non-finite value at step " + std::to_string(k), format_number(v[k]));
  };
  per_step(edge_displacement, "edge_displacement");
  per_step(edge_force, "edge_force");
  per_step(step_weight, "step_weight");
  for (int k = 0; k < static_cast<int>(step_weight.size()); ++k)
    if (!(step_weight[k] >= 0))
      fail("step_weight", "negative weight at step " + std::to_string(k), format_number(step_weight[k]), ">= 0");

  const int m = point_count();
  if (m > 0 || u.size() > 0 || v.size() > 0) {
    if (static_cast<int>(point_ids.size()) != m)
      fail("point_ids", "one id per point", std::to_string(point_ids.size()), std::to_string(m));
    std::set<int> seen;
    for (int id : point_ids)
      if (!seen.insert(id).second) fail("point_ids", "duplicate point id", std::to_string(id));
    for (int p = 0; p < m; ++p)
      if (!points.col(p).allFinite()) fail("points", "non-finite position of point " + std::to_string(point_ids[p]));
    auto field = [&](const Eigen::MatrixXd& F, const char* f) {
      if (F.rows() != n || F.cols() != m)
        fail(f, "steps × points values expected", std::to_string(F.rows()) + "×" + std::to_string(F.cols()),
             std::to_string(n) + "×" + std::to_string(m));
      for (int p = 0; p < m; ++p)
        for (int k = 0; k < n; ++k)
          if (!std::isfinite(F(k, p)))
            fail(f, "non-finite value at step " + std::to_string(k) + ", point " + std::to_string(point_ids[p]),
                 format_number(F(k, p)));
    };
    field(u, "u");
    field(v, "v");
    if (sigma_u.size() > 0 || sigma_v.size() > 0) {
      field(sigma_u, "sigma_u");
      field(sigma_v, "sigma_v");
      for (const auto* S : {&sigma_u, &sigma_v})
        if (!(S->minCoeff() > 0))
          fail(S == &sigma_u ? "sigma_u" : "sigma_v", "a per-point sigma must be > 0", format_number(S->minCoeff()),
               "> 0");
    }
  }
  for (auto [s, f] : {std::pair{sigma.edge_displacement, "sigma.edge_displacement"},
                      std::pair{sigma.edge_force, "sigma.edge_force"}, std::pair{sigma.field, "sigma.field"}})
    if (!(s >= 0) || !std::isfinite(s)) fail(f, "out of range", format_number(s), ">= 0 (0 = unknown)");
}

TestData TestData::select_steps(const std::vector<int>& keep) const {
  assert(field_kind == FieldKind::cumulative || !has_field());
  TestData d = *this;
  auto pick = [&](const std::vector<double>& v) {
    std::vector<double> out;
    if (!v.empty())
      for (int k : keep) out.push_back(v.at(static_cast<size_t>(k)));
    return out;
  };
  auto rows = [&](const Eigen::MatrixXd& m) { return m.size() == 0 ? m : Eigen::MatrixXd(m(keep, Eigen::all)); };
  d.loads = pick(loads), d.edge_displacement = pick(edge_displacement), d.edge_force = pick(edge_force);
  d.step_weight = pick(step_weight);
  d.u = rows(u), d.v = rows(v), d.sigma_u = rows(sigma_u), d.sigma_v = rows(sigma_v);
  return d;
}

void Experiment::validate() const {
  if (tests.empty()) throw InputError(Location{"", 0, "experiment"}, "no tests");
  std::set<std::string> names;
  for (const TestData& t : tests) {
    t.validate();
    if (!names.insert(t.name).second)
      throw InputError(Location{t.source, 0, "experiment." + t.name}, "duplicate test name");
  }
}

const TestData* Experiment::find(const std::string& name) const {
  for (const TestData& t : tests)
    if (t.name == name) return &t;
  return nullptr;
}

}  // namespace tricot::ident
