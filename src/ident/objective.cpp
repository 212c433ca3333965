// The FE objective (docs/theory.md §2, §7): simulate every test, take its values at the measured points and
// steps, scale them by eq. (1); the Jacobian from the FE sensitivities.
#include "tricot/ident/objective.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <optional>
#include <string>

#include "tricot/core/error.hpp"
#include "predict.hpp"

namespace tricot::ident {

namespace {

void check_weight(double w, const char* key) {
  if (!(w >= 0) || !std::isfinite(w)) throw InputError(Location{"", 0, key}, "out of range", format_number(w), ">= 0");
}

}  // namespace

void DataWeights::validate() const {
  check_weight(edge_displacement, "data.edge_displacement");
  check_weight(edge_force, "data.edge_force");
  check_weight(field, "data.field");
}

void ObjectiveOptions::validate() const {
  weights.validate();
  solver.validate();
  if (threads < 0 || threads > 1024)
    throw InputError(Location{"", 0, "identify.threads"}, "out of range", std::to_string(threads), "0 to 1024");
}

Objective::Objective(std::vector<fem::TestModel> models, Experiment experiment, const fem::Law& law,
                     std::vector<Parameter> parameters, ObjectiveOptions options)
    : experiment_(std::move(experiment)), law_(law.clone()), parameters_(std::move(parameters)),
      options_(std::move(options)) {
  options_.validate();
  experiment_.validate();

  // One model per test, in the experiment's order, with the same steps.
  for (const TestData& d : experiment_.tests) {
    auto it = std::find_if(models.begin(), models.end(), [&](const fem::TestModel& m) { return m.name == d.name; });
    if (it == models.end())
      throw InputError(Location{d.source, 0, "experiment." + d.name}, "no test model of that name");
    it->validate();
    const double tol = 1e-9 * std::max(std::abs(d.loads.back()), std::abs(it->loads.back()));
    bool same = it->loads.size() == d.loads.size();
    for (size_t k = 0; same && k < d.loads.size(); ++k) same = std::abs(it->loads[k] - d.loads[k]) <= tol;
    if (!same)
      throw InputError(Location{d.source, 0, "experiment." + d.name + ".loads"},
                       "the measured steps differ from the model's", std::to_string(d.loads.size()) + " steps",
                       "the model's " + std::to_string(it->loads.size()) + " loads");
    models_.push_back(*it);
  }
  for (const fem::TestModel& m : models)
    if (!experiment_.find(m.name))
      throw InputError(Location{"", 0, "test." + m.name}, "test model without data in the experiment");

  // Parameters: coefficients of the law (a NaN start is the law's value), then force scales
  // `<test>.force_scale` (a NaN start is 1).
  const std::vector<std::string> names = law_->coefficient_names();
  const Eigen::VectorXd c0 = law_->coefficients();
  scale_of_test_.assign(models_.size(), -1);
  for (std::size_t k = 0; k < parameters_.size(); ++k) {
    Parameter& p = parameters_[k];
    const auto it = std::find(names.begin(), names.end(), p.name);
    if (it != names.end()) {
      if (coefficient_.size() != k)
        throw std::logic_error("Objective: the law's coefficients must come before the force scales (" + p.name + ")");
      coefficient_.push_back(static_cast<int>(it - names.begin()));
      if (std::isnan(p.start)) p.start = c0(coefficient_.back());
      continue;
    }
    const std::string test = force_scale_test(p.name);
    if (test.empty()) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw InputError(Location{"", 0, "parameters." + p.name}, "not a coefficient of the " + law_->name() + " law",
                       p.name, "one of " + list + ", or <test>." + kForceScale);
    }
    if (std::isnan(p.start)) p.start = 1;
    for (std::size_t t = 0; t < models_.size(); ++t) {
      if (models_[t].name != test) continue;
      if (models_[t].control == fem::GripControl::force)
        throw InputError(Location{"", 0, "parameters." + p.name}, "a force scale needs a displacement-controlled grip",
                         "test " + test + " under force control", "control = \"displacement\"");
      scale_of_test_[t] = static_cast<int>(k);
    }
  }
#ifndef NDEBUG
  validate(parameters_);  // the caller's check (project: IdentificationSpec::validate); trusted in release
#endif

  after_ = options_.sensitivities_after && std::all_of(models_.begin(), models_.end(), [](const fem::TestModel& m) {
             return m.mesh.dofs() < fem::kSensitivitiesAfterBelow;
           });

  // The evaluation order: the largest nominal strains first, ² summed over the pull (grip
  // displacement over the quarter's height) and across it (guide over the quarter's width); a
  // force-controlled grip counts by its guide only. Ties keep the experiment's order.
  std::vector<double> stretch(models_.size(), 0.0);
  for (size_t t = 0; t < models_.size(); ++t) {
    const fem::TestModel& m = models_[t];
    const double W = m.mesh.X.row(0).maxCoeff() - m.mesh.X.row(0).minCoeff();
    const double H = m.mesh.X.row(1).maxCoeff() - m.mesh.X.row(1).minCoeff();
    const double pull =
        m.control == fem::GripControl::displacement && !m.loads.empty() && H > 0 ? m.loads.back() / H : 0;
    double across = 0;
    for (double g : m.guide) across = std::max(across, W > 0 ? std::abs(g) / W : 0.0);
    stretch[t] = pull * pull + across * across;
  }
  order_.resize(models_.size());
  for (size_t t = 0; t < models_.size(); ++t) order_[t] = static_cast<int>(t);
  std::stable_sort(order_.begin(), order_.end(), [&](int a, int b) { return stretch[a] > stretch[b]; });
  rank_.resize(models_.size());
  for (size_t k = 0; k < order_.size(); ++k) rank_[order_[k]] = static_cast<int>(k);

  // Field points: located once in each reference mesh; all must be inside.
  for (size_t t = 0; t < models_.size(); ++t)
    reference_locations_.push_back(detail::locate_points(models_[t], experiment_.tests[t]));

  // Data groups (docs/theory.md §2).
  const DataWeights& w = options_.weights;
  data_ = ScaledResiduals(w.fixed);
  for (size_t t = 0; t < models_.size(); ++t) {
    const TestData& d = experiment_.tests[t];
    const size_t first_group = data_.groups().size();
    const int ti = static_cast<int>(t);
    const bool force_control = models_[t].control == fem::GripControl::force;
    auto to_vec = [](const std::vector<double>& v) { return Eigen::Map<const Eigen::VectorXd>(v.data(), v.size()); };
    if (w.edge_displacement > 0 && force_control && !d.edge_displacement.empty())
      data_.add(d.name + "/edge_displacement", GroupKind::edge_displacement, ti, to_vec(d.edge_displacement),
                w.edge_displacement, d.sigma.edge_displacement);
    if (w.edge_force > 0 && !force_control && !d.edge_force.empty())
      data_.add(d.name + "/edge_force", GroupKind::edge_force, ti, to_vec(d.edge_force), w.edge_force,
                d.sigma.edge_force);
    const bool per_point = d.sigma_u.size() > 0 && d.sigma_v.size() > 0;
    if (w.field > 0 && d.has_field() && per_point) {  // the DIC's σ of every value (docs/theory.md §8)
      if (w.field_uv) {
        data_.add(d.name + "/field_uv", GroupKind::field_uv, ti, detail::stack_uv(d.u, d.v), w.field,
                  detail::stack_uv(d.sigma_u, d.sigma_v));
      } else {
        data_.add(d.name + "/field_u", GroupKind::field_u, ti, detail::stack(d.u), w.field, detail::stack(d.sigma_u));
        data_.add(d.name + "/field_v", GroupKind::field_v, ti, detail::stack(d.v), w.field, detail::stack(d.sigma_v));
      }
    } else if (w.field > 0 && d.has_field()) {
      if (w.field_uv) {
        data_.add(d.name + "/field_uv", GroupKind::field_uv, ti, detail::stack_uv(d.u, d.v), w.field, d.sigma.field);
      } else {
        data_.add(d.name + "/field_u", GroupKind::field_u, ti, detail::stack(d.u), w.field, d.sigma.field);
        data_.add(d.name + "/field_v", GroupKind::field_v, ti, detail::stack(d.v), w.field, d.sigma.field);
      }
    }
    if (d.step_weight.empty()) continue;
    // The test's per-step weights, on every row of that step (field groups: step-major, docs/theory.md §2).
    const Eigen::Map<const Eigen::VectorXd> omega(d.step_weight.data(),
                                                  static_cast<Eigen::Index>(d.step_weight.size()));
    for (size_t gi = first_group; gi < data_.groups().size(); ++gi) {
      const DataGroup& g = data_.groups()[gi];
      const int per_step = g.size / d.steps();
      data_.weight_rows(g, omega.replicate(1, per_step).transpose().reshaped());
    }
  }
  bool scaled = false, unscaled = false;
  for (const DataGroup& g : data_.groups())
    if (g.kind == GroupKind::edge_force) (scale_of_test_[g.test] >= 0 ? scaled : unscaled) = true;
  if (scaled && !unscaled)
    throw InputError(Location{"", 0, "parameters"}, "every test's force is scaled, so nothing sets the law's scale",
                     std::string("a <test>.") + kForceScale + " for every test with force data",
                     "one test at least (one per direction) without a force scale: its specimen is the reference");
  if (data_.size() == 0)
    throw InputError(Location{"", 0, "data"}, "no data selected", "",
                     "edge displacement (force control), edge force (displacement control) or field data "
                     "with a weight > 0");
}

double Objective::force_scale(const Eigen::VectorXd& J, int test) const {
  const int s = scale_of_test_[static_cast<std::size_t>(test)];
  return s < 0 ? 1.0 : J(s);
}

std::unique_ptr<fem::Law> Objective::law_at(const Eigen::VectorXd& J) const {
  auto law = law_->clone();
  Eigen::VectorXd c = law->coefficients();
  for (size_t k = 0; k < coefficient_.size(); ++k) c(coefficient_[k]) = J(static_cast<Eigen::Index>(k));
  law->set_coefficients(c);
  return law;
}

std::vector<TestValues> Objective::evaluate_tests(const Eigen::VectorXd& J, bool jacobian,
                                                  const std::vector<int>& tests) const {
  const int T = static_cast<int>(models_.size());
  std::vector<TestValues> values(T);
  std::unique_ptr<fem::Law> law;
  try {
    law = law_at(J);
  } catch (const std::exception& e) {
    for (int t : tests) values[t].message = std::string("coefficients rejected by the law: ") + e.what();
    return values;
  }
  fem::SolveOptions so = options_.solver;
  const bool after = after_;
  so.sensitivities = jacobian && !after;  // else added afterwards (fem::add_sensitivities)
  so.keep_residuals = false;
  std::vector<std::optional<fem::SimulationResult>> kept(T);
  if (after) {
    const std::lock_guard<std::mutex> lock(simulated_mutex_);
    for (const Simulated& s : simulated_)
      if (s.J.size() == J.size() && s.J == J) {
        kept = s.tests;
        break;
      }
  }
  std::shared_ptr<const Warm> warm;
  if (options_.warm_start) {
    const std::lock_guard<std::mutex> lock(simulated_mutex_);
    warm = warm_;
  }
  const Eigen::VectorXd dc = warm ? Eigen::VectorXd(law->coefficients() - warm->c) : Eigen::VectorXd();
  std::vector<std::optional<fem::SimulationResult>> fresh(T), solved(options_.warm_start && jacobian ? T : 0);
  // A failed test fails the evaluation: the tests after the first failed one (in order_) are not run,
  // or stop at their next increment. The first failing test always runs to its end, whatever the
  // threads do, so the evaluation's message is the same on any number of threads. first_failed holds
  // its rank.
  std::vector<int> run(tests);
  std::sort(run.begin(), run.end(), [&](int a, int b) { return rank_[a] < rank_[b]; });
  std::atomic<int> first_failed{T};
  const auto failed = [&first_failed](int t) {
    int current = first_failed.load();
    while (t < current && !first_failed.compare_exchange_weak(current, t)) {}
  };
  const int threads = thread_team(options_.threads);
  const int K = static_cast<int>(run.size());
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (int k = 0; k < K; ++k) {
    const int t = run[k], rank = rank_[t];
    if (first_failed.load(std::memory_order_relaxed) < rank) continue;
    fem::SolveOptions st = so;
    st.cancelled = [&first_failed, rank] { return first_failed.load(std::memory_order_relaxed) < rank; };
    if (warm && warm->tests[t]) st.warm_start = &*warm->tests[t], st.warm_start_dc = dc;
    TestValues& v = values[t];
    detail::Prediction P;
    try {
      fem::SimulationResult sim = kept[t] ? std::move(*kept[t]) : fem::simulate(models_[t], *law, st);
      if (!sim.usable()) {
        v.message = "test " + models_[t].name + ": " + sim.message;
        failed(rank);
        continue;
      }
      if (after && !jacobian) fresh[t] = sim;
      if (after && jacobian && !fem::add_sensitivities(models_[t], *law, sim, st)) {
        v.message = "test " + models_[t].name + ": " + sim.message;
        failed(rank);
        continue;
      }
      v.ok = detail::predict(models_[t], experiment_.tests[t], reference_locations_[t], sim,
                             jacobian ? &coefficient_ : nullptr, P, v.message);
      if (v.ok && !solved.empty()) solved[t] = std::move(sim);
    } catch (const std::exception& e) {
      v.message = "test " + models_[t].name + ": " + e.what();
    }
    if (!v.ok) {
      failed(rank);
      continue;
    }
    // The test's rows of y, its data groups one after the other (as evaluate() reads them back).
    int rows = 0;
    for (const DataGroup& g : data_.groups())
      if (g.test == t) rows += g.size;
    v.y.resize(rows);
    if (jacobian) v.dy_dJ.setZero(rows, static_cast<Eigen::Index>(parameters_.size()));
    const Eigen::Index nl = static_cast<Eigen::Index>(coefficient_.size());  // the law's columns
    int row = 0;
    for (const DataGroup& g : data_.groups()) {
      if (g.test != t) continue;
      switch (g.kind) {
        case GroupKind::edge_displacement:
          v.y.segment(row, g.size) = P.edge_displacement;
          if (jacobian) v.dy_dJ.middleRows(row, g.size).leftCols(nl) = P.dedge_displacement_dc;
          break;
        case GroupKind::edge_force:
          v.y.segment(row, g.size) = P.edge_force;
          if (jacobian) v.dy_dJ.middleRows(row, g.size).leftCols(nl) = P.dedge_force_dc;
          break;
        case GroupKind::field_u:
          v.y.segment(row, g.size) = detail::stack(P.U);
          if (jacobian) v.dy_dJ.middleRows(row, g.size).leftCols(nl) = P.dU_dc;
          break;
        case GroupKind::field_v:
          v.y.segment(row, g.size) = detail::stack(P.V);
          if (jacobian) v.dy_dJ.middleRows(row, g.size).leftCols(nl) = P.dV_dc;
          break;
        case GroupKind::field_uv:
          v.y.segment(row, g.size) = detail::stack_uv(P.U, P.V);
          if (jacobian)
            for (Eigen::Index i = 0; i < P.dU_dc.rows(); ++i) {
              v.dy_dJ.row(row + 2 * i).head(nl) = P.dU_dc.row(i);
              v.dy_dJ.row(row + 2 * i + 1).head(nl) = P.dV_dc.row(i);
            }
          break;
      }
      row += g.size;
    }
  }
  if (!solved.empty() && std::all_of(tests.begin(), tests.end(), [&](int t) { return values[t].ok; })) {
    auto next = std::make_shared<Warm>(Warm{law->coefficients(), std::move(solved)});
    const std::lock_guard<std::mutex> lock(simulated_mutex_);
    warm_ = std::move(next);
  }
  if (after && !jacobian && std::any_of(fresh.begin(), fresh.end(), [](const auto& f) { return f.has_value(); })) {
    const std::lock_guard<std::mutex> lock(simulated_mutex_);
    simulated_.push_front({J, std::move(fresh)});
    if (simulated_.size() > kSimulated) simulated_.pop_back();
  }
  return values;
}

std::vector<fem::SimulationResult> Objective::simulations(const Eigen::VectorXd& J) const {
  const std::unique_ptr<fem::Law> law = law_at(J);
  const int T = static_cast<int>(models_.size());
  std::vector<fem::SimulationResult> out(T);
  std::vector<bool> have(T, false);
  {
    const std::lock_guard<std::mutex> lock(simulated_mutex_);
    if (warm_ && warm_->c == law->coefficients())
      for (int t = 0; t < T; ++t)
        if (warm_->tests[t]) out[t] = *warm_->tests[t], have[t] = true;
    for (const Simulated& s : simulated_)
      if (s.J.size() == J.size() && s.J == J)
        for (int t = 0; t < T; ++t)
          if (!have[t] && s.tests[t]) out[t] = *s.tests[t], have[t] = true;
  }
  const int threads = thread_team(options_.threads);
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (int k = 0; k < T; ++k) {
    const int t = order_[k];
    if (!have[t]) out[t] = fem::simulate(models_[t], *law, options_.solver);
  }
  return out;
}

Evaluation Objective::evaluate(const Eigen::VectorXd& J, bool jacobian) const {
  if (jacobian) {
    const std::lock_guard<std::mutex> lock(simulated_mutex_);
    if (last_jacobian_ && last_jacobian_at_.size() == J.size() && last_jacobian_at_ == J) {
      Evaluation again = *last_jacobian_;
      again.evaluations = 0;  // no FE ran
      return again;
    }
  }
  Evaluation out = evaluate_afresh(J, jacobian);
  if (jacobian && out.ok) {
    const std::lock_guard<std::mutex> lock(simulated_mutex_);
    last_jacobian_ = out, last_jacobian_at_ = J;
  }
  return out;
}

Evaluation Objective::evaluate_afresh(const Eigen::VectorXd& J, bool jacobian) const {
  Evaluation out;
  out.evaluations = 1;
  const int T = static_cast<int>(models_.size());
  const auto local = [&](const std::vector<int>& tests) { return evaluate_tests(J, jacobian, tests); };
  std::vector<TestValues> values;
  if (split_) {
    values = split_->evaluate(J, jacobian, T, local);
  } else {
    std::vector<int> all(T);
    for (int t = 0; t < T; ++t) all[t] = t;
    values = local(all);
  }
  for (int t : order_)  // the first failed test in the evaluation order
    if (!values[t].ok) {
      out.message = values[t].message;
      return out;
    }

  // y and ∂y/∂J from the tests' rows, group by group in the data's order.
  const int N = data_.size(), n = static_cast<int>(parameters_.size());
  out.y.resize(N);
  Eigen::MatrixXd dy_dJ;
  if (jacobian) dy_dJ.setZero(N, n);
  std::vector<int> row(T, 0);
  for (const DataGroup& g : data_.groups()) {
    const TestValues& v = values[g.test];
    out.y.segment(g.offset, g.size) = v.y.segment(row[g.test], g.size);
    if (jacobian) dy_dJ.middleRows(g.offset, g.size) = v.dy_dJ.middleRows(row[g.test], g.size);
    row[g.test] += g.size;
  }
  // Force scales: a scaled test's grip force is k times the law's (its field does not change: under a
  // displacement-controlled grip the FE's displacements do not depend on the forces' scale).
  for (const DataGroup& g : data_.groups()) {
    const int s = g.kind == GroupKind::edge_force ? scale_of_test_[g.test] : -1;
    if (s < 0) continue;
    const double k = J(s);
    if (jacobian) {
      dy_dJ.block(g.offset, 0, g.size, static_cast<Eigen::Index>(coefficient_.size())) *= k;
      dy_dJ.col(s).segment(g.offset, g.size) = out.y.segment(g.offset, g.size);
    }
    out.y.segment(g.offset, g.size) *= k;
  }
  out.r = data_.residuals(out.y);
  if (jacobian) {
    data_.scale_rows(dy_dJ);
    out.jacobian = std::move(dy_dJ);
  }
  out.ok = true;
  return out;
}

}  // namespace tricot::ident
