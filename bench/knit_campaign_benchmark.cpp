// The paper's §4 campaign through the engine APIs (issue 12): biaxial-induced tests on the rig
// (fem::make_rig_test) synthesised from the reference knit on a finer mesh, then the response
// surface `paper14` / `paper24` identified from the field and the grip force of all tests together on
// the paper's 120 Q8 elements. Reports Table 4 (objective, iterations, evaluations, wall time,
// condition number, largest correlation) and Table 5 (eq. 9, whole and practical range, course and
// wale) as counters, beside the paper's values, and prints the campaign's field spreads, the
// identifiability report and a D-optimal added test once per run.
//
//   build/bench/knit_campaign_benchmark --benchmark_filter=110/paper14
#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <atomic>
#include <thread>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <chrono>
#include <stdexcept>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "tricot/core/error.hpp"
#include "tricot/core/kinematics.hpp"
#include "tricot/fem/element.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/response_surface.hpp"
#include "tricot/fem/rig.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/identifiability.hpp"
#include "tricot/ident/identify.hpp"
#include "tricot/fem/wrinkling.hpp"
#include "tricot/ident/objective.hpp"
#include "tricot/ident/stability_barrier.hpp"
#include "tricot/ident/surface_error.hpp"
#include "tricot/ident/synthetic.hpp"

namespace {

using namespace tricot;

constexpr double kShear = 0.05;  // G_s of the truth and of the identified surface (not identified)

/// One specimen size of the campaign (docs/theory.md §6; issue 12).
struct CampaignSpec {
  double side;
  int steps;
  double wale_pull, course_pull;        // GL strain along the pull at the last step
  std::vector<double> course_settings;  // transverse course strains of the wale-pulled tests
  std::vector<double> wale_settings;    // transverse wale strains of the course-pulled tests
};
const CampaignSpec k110{110, 21, 0.65, 1.0, {0, 0.2, 0.4, 0.55, 0.7}, {0, 0.15, 0.3, 0.45, 0.6}};
const CampaignSpec k150{150, 28, 0.35, 0.45, {0, 0.15, 0.3, 0.45}, {0, 0.12, 0.24, 0.35}};

/// TRICOT_CAMPAIGN_WRINKLING: the truth and the identified surface as tension-field membranes, the
/// clips holding their whole width, as examples/knit-campaign (docs/theory/fabric.md §8).
bool wrinkling() { return std::getenv("TRICOT_CAMPAIGN_WRINKLING") != nullptr; }

fem::RigOptions rig(const CampaignSpec& s, fem::PullDirection pull, double transverse, int nx, int ny) {
  fem::RigOptions o;
  if (wrinkling()) o.clip_taper = 0;
  o.side = s.side, o.pull = pull, o.transverse_strain = transverse, o.steps = s.steps;
  o.pull_strain = pull == fem::PullDirection::wale ? s.wale_pull : s.course_pull;
  o.name = std::string(to_string(pull)) + "-" + std::to_string(static_cast<int>(std::lround(100 * transverse)));
  o.nx = nx, o.ny = ny;
  return o;
}

/// A test of the campaign: coarse model (identification), data from the fine one, and the strains
/// at the specimen centre per step (the "DIC" strains of eq. 9's points).
struct CampaignTest {
  fem::PullDirection pull;
  double transverse;
  fem::TestModel model;
  ident::TestData data;
  std::vector<Eigen::Vector2d> centre;  // (εC, εW) per step
  fem::StrainSpread last;
};

struct Campaign {
  CampaignSpec spec;
  std::vector<CampaignTest> tests;
  double synth_seconds = 0;
};

CampaignTest synthesise(const CampaignSpec& s, fem::PullDirection pull, double transverse) {
  const fem::ReferenceFabric truth([] {
    fem::ReferenceFabricParameters p;
    p.G_s = kShear;
    return p;
  }());
  CampaignTest t{pull, transverse, fem::make_rig_test(rig(s, pull, transverse, 12, 10)), {}, {}, {}};
  const fem::TestModel fine = fem::make_rig_test(rig(s, pull, transverse, 24, 20));
  const fem::SimulationResult r =
      wrinkling() ? fem::simulate(fine, fem::WrinklingLaw(truth)) : fem::simulate(fine, truth);
  if (!r.usable()) throw std::runtime_error(r.message);
  // The example's field points (examples/knit-campaign/experiment.toml, [synth] inset = 9, spacing =
  // 18): the material points that tricot demo's DIC tracks, every 18 mm from 9 mm up to 9 mm short of
  // the quarter's edges (3 × 3 on 110, 4 × 4 on 150). Until stop 22: a 6 × 6 grid from 0.05 h.
  const double h = 0.5 * s.side;
  std::vector<double> axis;
  for (double x = 9; x <= h - 9 + 1e-9; x += 18) axis.push_back(x);
  const auto m = static_cast<Eigen::Index>(axis.size());
  Eigen::Matrix2Xd points(2, m * m);
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = 0; i < m; ++i) points.col(m * j + i) = Eigen::Vector2d(axis[i], axis[j]);
  t.data = ident::measure(fine, r, points);
  for (const auto& step : r.steps) {
    const fem::StrainSpread sp = fem::strain_spread(fine, step.u);
    t.centre.emplace_back(sp.eC_centre, sp.eW_centre);
  }
  t.last = fem::strain_spread(fine, r.steps.back().u);
  return t;
}

Campaign& campaign(int size) {
  static std::map<int, Campaign> cache;
  auto it = cache.find(size);
  if (it != cache.end()) return it->second;
  Campaign c;
  c.spec = size == 110 ? k110 : k150;
  const auto t0 = std::chrono::steady_clock::now();
  for (double x : c.spec.course_settings) c.tests.push_back(synthesise(c.spec, fem::PullDirection::wale, x));
  for (double x : c.spec.wale_settings) c.tests.push_back(synthesise(c.spec, fem::PullDirection::course, x));
  c.synth_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("\n# %d x %d campaign: %zu tests x %d steps (data: 24 x 20 Q8, %.1f s)\n", size, size, c.tests.size(),
              c.spec.steps, c.synth_seconds);
  std::printf("# test         eC range at last step   eW range at last step   centre (eC, eW)\n");
  for (const auto& t : c.tests)
    std::printf("# %-12s [%6.3f, %6.3f]        [%6.3f, %6.3f]        (%.3f, %.3f)\n", t.model.name.c_str(),
                t.last.eC_min, t.last.eC_max, t.last.eW_min, t.last.eW_max, t.last.eC_centre, t.last.eW_centre);
  return cache.emplace(size, std::move(c)).first->second;
}

/// Eq. 9's points (docs/theory.md §9): course points from the course-pulled tests, wale from wale-pulled.
std::vector<ident::SurfacePoint> surface_points(const Campaign& c, fem::PullDirection pull,
                                                bool (*keep)(const CampaignTest&, int)) {
  std::vector<ident::SurfacePoint> p;
  for (const auto& t : c.tests) {
    if (t.pull != pull) continue;
    for (int k = 0; k < t.data.steps(); ++k)
      if (!keep || keep(t, k)) p.push_back({t.centre[k](0), t.centre[k](1), t.data.edge_force[k] / c.spec.side});
  }
  return p;
}

/// The smallest eigenvalue of the symmetric part of ∂(F_C, F_W)/∂(εC, εW) [N/mm] over the strains
/// the rig's fields reach (εC ∈ [−0.4, 1.3] × εW ∈ [−0.4, 1.4], step 0.05): < 0 means the law has a
/// softening or an unstable coupling somewhere the FE goes, and Newton fails there.
double smallest_stiffness(const fem::ResponseSurface& law, double* at_C = nullptr, double* at_W = nullptr) {
  double worst = 1e300;
  constexpr double h = 1e-6;  // central differences of a C¹ polynomial: error O(h²)
  for (int i = 0; i <= 34; ++i)
    for (int j = 0; j <= 36; ++j) {
      const double eC = -0.4 + 0.05 * i, eW = -0.4 + 0.05 * j;
      Eigen::Matrix2d A;
      A.col(0) = (law.forces(eC + h, eW) - law.forces(eC - h, eW)) / (2 * h);
      A.col(1) = (law.forces(eC, eW + h) - law.forces(eC, eW - h)) / (2 * h);
      const double m = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(0.5 * (A + A.transpose())).eigenvalues()(0);
      if (m < worst) {
        worst = m;
        if (at_C) *at_C = eC, *at_W = eW;
      }
    }
  return worst;
}

/// LM's start: each force's monomials fitted by linear least squares to its eq. 9 points (through
/// the law's own basis), ridge-regularised toward the own-direction slope fit (a1 and c1 only) in
/// column-normalised units: x(λ) = argmin |A x − b|² + λ |x − x_slope|². λ is the smallest of 0,
/// 1e-6 … 1e2 (×10) whose law is stable over the fields' strains (smallest_stiffness > 0): the plain
/// fit extrapolates to the high strains at the clips (εW ≈ 1.3 where the centre reaches 0.65) and
/// to negative stiffness there. With max_degree = 1, the slope fit itself.
Eigen::VectorXd polynomial_start(const fem::ResponseSurface& law, const Campaign& c, int max_degree = 99) {
  const Eigen::Index n = law.coefficients().size();
  const Eigen::Index nc = static_cast<Eigen::Index>(law.course_monomials().size());
  fem::ResponseSurface unit = law;
  std::array<Eigen::MatrixXd, 2> A;
  std::array<Eigen::VectorXd, 2> b, x_slope, norms;
  for (int force = 0; force < 2; ++force) {
    const Eigen::Index col = force == 0 ? 0 : nc, m = force == 0 ? nc : n - nc;
    const auto pts = surface_points(c, force == 0 ? fem::PullDirection::course : fem::PullDirection::wale, nullptr);
    A[force].resize(static_cast<Eigen::Index>(pts.size()), m);
    b[force].resize(static_cast<Eigen::Index>(pts.size()));
    for (Eigen::Index k = 0; k < m; ++k) {
      unit.set_coefficients(Eigen::VectorXd::Unit(n, col + k));
      for (size_t i = 0; i < pts.size(); ++i) A[force](i, k) = unit.forces(pts[i].eC, pts[i].eW)(force);
    }
    for (size_t i = 0; i < pts.size(); ++i) b[force](i) = pts[i].force;
    norms[force] = A[force].colwise().norm().transpose();
    A[force] = A[force] * norms[force].cwiseInverse().asDiagonal();
    // The own-direction monomial is the first of each list (a1: εC in F_C; c1: εW in F_W).
    x_slope[force] = Eigen::VectorXd::Zero(m);
    x_slope[force](0) = A[force].col(0).dot(b[force]) / A[force].col(0).squaredNorm();
  }
  auto solve = [&](double lambda) {
    Eigen::VectorXd J(n);
    for (int force = 0; force < 2; ++force) {
      const Eigen::Index m = A[force].cols();
      const Eigen::MatrixXd M = A[force].transpose() * A[force] + lambda * Eigen::MatrixXd::Identity(m, m);
      const Eigen::VectorXd x =
          M.colPivHouseholderQr().solve(A[force].transpose() * b[force] + lambda * x_slope[force]);
      J.segment(force == 0 ? 0 : nc, m) = x.cwiseQuotient(norms[force]);
    }
    return J;
  };
  if (max_degree <= 1) return solve(1e12);
  fem::ResponseSurface trial = law;
  for (double lambda : {0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0}) {
    const Eigen::VectorXd J = solve(lambda);
    trial.set_coefficients(J);
    if (smallest_stiffness(trial) > 0) {
      std::printf("# start: ridge lambda = %g (smallest stiffness %.3g N/mm)\n", lambda, smallest_stiffness(trial));
      return J;
    }
  }
  return solve(1e12);
}

/// Diagnosis (TRICOT_CAMPAIGN_PROBE="J1,…,J14[;s]"): the 110 mm models run with paper14 at
/// J* + s (J* − J_start), printing each test's status and, step by step, the strains, the tangent
/// determinant of (F_C, F_W) and det F at the centre of the element that inverts (TRICOT_PROBE_ELEMENT,
/// default 107) and of its neighbours.
void probe(const char* spec) {
  std::vector<double> v;
  double s = 0;
  std::string text(spec);
  const auto semi = text.find(';');
  if (semi != std::string::npos) s = std::atof(text.c_str() + semi + 1), text = text.substr(0, semi);
  for (size_t a = 0; a < text.size();) {
    size_t b = text.find(',', a);
    if (b == std::string::npos) b = text.size();
    v.push_back(std::atof(text.substr(a, b - a).c_str()));
    a = b + 1;
  }
  Campaign& c = campaign(110);
  fem::ResponseSurface law = fem::ResponseSurface::preset("paper14", kShear);
  const Eigen::VectorXd J_star = Eigen::Map<Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  const Eigen::VectorXd J0 = polynomial_start(law, c);
  law.set_coefficients(J_star + s * (J_star - J0));
  const int watch = std::getenv("TRICOT_PROBE_ELEMENT") ? std::atoi(std::getenv("TRICOT_PROBE_ELEMENT")) : 107;
  for (const auto& t : c.tests) {
    const fem::SimulationResult r = fem::simulate(t.model, law);
    std::printf("# probe s=%g %s: %s %s (%zu steps)\n", s, t.model.name.c_str(), fem::to_string(r.termination),
                r.message.c_str(), r.steps.size());
    if (r.usable()) continue;
    const Eigen::Matrix2d Q = t.pull == fem::PullDirection::wale ? Eigen::Matrix2d::Identity()
                                                                 : Eigen::Matrix2d(Eigen::Rotation2Dd(M_PI / 2));
    (void)Q;
    for (size_t k = 0; k < r.steps.size(); ++k)
      for (int e : {watch - 12, watch - 1, watch, watch + 12}) {
        if (e < 0 || e >= t.model.mesh.elements()) continue;
        const Mat2 F = fem::deformation_gradient(t.model.mesh, e, Vec2::Zero(), r.steps[k].u);
        Mat2 Qm;
        Qm << std::cos(M_PI / 180 * t.model.material_angle), -std::sin(M_PI / 180 * t.model.material_angle),
            std::sin(M_PI / 180 * t.model.material_angle), std::cos(M_PI / 180 * t.model.material_angle);
        const Mat2 E = Qm.transpose() * green_lagrange(F) * Qm;
        const double h = 1e-6;
        Eigen::Matrix2d A;
        A.col(0) = (law.forces(E(0, 0) + h, E(1, 1)) - law.forces(E(0, 0) - h, E(1, 1))) / (2 * h);
        A.col(1) = (law.forces(E(0, 0), E(1, 1) + h) - law.forces(E(0, 0), E(1, 1) - h)) / (2 * h);
        const Vec2 f = law.forces(E(0, 0), E(1, 1));
        std::printf(
            "#   step %2zu el %3d: eC %7.3f eW %7.3f eCW %7.3f detF %6.3f  F_C %7.4f F_W %7.4f  det dF/de %8.4f\n",
            k + 1, e, E(0, 0), E(1, 1), E(0, 1), F.determinant(), f(0), f(1), A.determinant());
      }
  }
}

struct Surfaces {
  ident::Eq9Error course, wale;            // against the experimental points (Table 5)
  ident::Eq9Error course_true, wale_true;  // against the reference knit at the same strains
};

/// eq9_error, or only the whole-range mean when the practical domain holds no point (the 150 mm
/// campaign stops at 45 % course: its practical error is reported as NaN).
ident::Eq9Error eq9(const std::vector<ident::SurfacePoint>& p, const std::function<double(double, double)>& f) {
  try {
    return ident::eq9_error(p, f);
  } catch (const InputError&) {
    ident::StrainDomain all;
    all.eC_min = all.eW_min = -1e9, all.eC_max = all.eW_max = 1e9;
    ident::Eq9Error e = ident::eq9_error(p, f, all);
    e.practical = NAN, e.points_practical = 0;
    return e;
  }
}

Surfaces errors(const Campaign& c, const fem::ResponseSurface& law) {
  const fem::ReferenceFabric truth;
  Surfaces s;
  const auto pc = surface_points(c, fem::PullDirection::course, nullptr);
  const auto pw = surface_points(c, fem::PullDirection::wale, nullptr);
  s.course = eq9(pc, [&](double a, double b) { return law.forces(a, b)(0); });
  s.wale = eq9(pw, [&](double a, double b) { return law.forces(a, b)(1); });
  auto as_truth = [&](std::vector<ident::SurfacePoint> p, int i) {
    for (auto& x : p) x.force = truth.forces(x.eC, x.eW)(i);
    return p;
  };
  s.course_true = eq9(as_truth(pc, 0), [&](double a, double b) { return law.forces(a, b)(0); });
  s.wale_true = eq9(as_truth(pw, 1), [&](double a, double b) { return law.forces(a, b)(1); });
  return s;
}

struct Run {
  ident::IdentifyResult result;
  std::unique_ptr<ident::Objective> objective;
  std::unique_ptr<ident::StabilizedObjective> stabilized;  // the objective with the stability barrier
  Surfaces start_errors, errors, truth_errors;
};

Run identify(const Campaign& c, const std::string& preset, bool restricted) {
  fem::ResponseSurface law = fem::ResponseSurface::preset(preset, kShear);
  const Eigen::VectorXd J_fit = polynomial_start(law, c);
  Eigen::VectorXd J0 = std::getenv("TRICOT_CAMPAIGN_SLOPE_START") ? polynomial_start(law, c, 1) : J_fit;
  // TRICOT_CAMPAIGN_JITTER=seed: each start coefficient × (1 + u), u uniform in ±1 % (the path's
  // sensitivity to its start: docs/validation.md §5).
  if (const char* seed = std::getenv("TRICOT_CAMPAIGN_JITTER")) {
    std::mt19937 g(static_cast<unsigned>(std::strtoul(seed, nullptr, 10)));
    std::uniform_real_distribution<double> u(-0.01, 0.01);
    for (Eigen::Index k = 0; k < J0.size(); ++k) J0(k) *= 1 + u(g);
  }
  law.set_coefficients(J_fit);
  const Surfaces fit_errors = errors(c, law);
  std::printf("# start (%s): coefficients = [", preset.c_str());
  for (Eigen::Index k = 0; k < J_fit.size(); ++k) std::printf("%s%.6g", k ? ", " : "", J_fit(k));
  std::printf("]\n");
  law.set_coefficients(J0);
  std::vector<fem::TestModel> models;
  ident::Experiment data;
  for (const auto& t : c.tests) models.push_back(t.model), data.tests.push_back(t.data);
  if (restricted) {  // the practical domain ± 0.1, as examples/knit-campaign/project-110-restricted.toml
    ident::StrainDomain d;
    d.eC_min = 0.5, d.eC_max = 1.1, d.eW_min = 0.1, d.eW_max = 0.5;
    ident::Restriction r = ident::restrict_to_domain(models, data, d);
    models = std::move(r.models), data = std::move(r.experiment);
  }
  std::vector<ident::Parameter> p;
  const auto names = law.coefficient_names();
  for (size_t k = 0; k < names.size(); ++k) {
    ident::Parameter q;
    q.name = names[k], q.start = J0(k), q.scale = std::max(std::abs(J_fit(k)), 1e-3);
    // A knit locks, it never softens in tension: the leading own-direction coefficient (a6; c4 or
    // c6) is kept ≥ 0, so the surface stiffens at the clips' strains beyond the data (εW ≈ 1.3).
    if (q.name == "a6" || q.name == (preset == "paper14" ? "c4" : "c6")) q.lower = 0, q.start = std::max(q.start, 0.0);
    p.push_back(q);
  }
  Run run;
  ident::ObjectiveOptions oo;
  oo.sensitivities_after = true;  // as a project with bounds (identification_spec.cpp)
  run.objective = wrinkling() ? std::make_unique<ident::Objective>(models, data, fem::WrinklingLaw(law), p, oo)
                              : std::make_unique<ident::Objective>(models, data, law, p, oo);
  ident::IdentifyOptions o;
  o.initial_trust_region_radius = 100,
  o.line_search_trials = 4;  // examples/knit-campaign/project-110.toml's [identify]
  o.active_set = true;       // as project-110.toml (docs/validation.md §5)
  // TRICOT_CAMPAIGN_BARRIER_GROWTH: identify.barrier_growth (0 = LM's steps not cut at the barrier).
  if (const char* g = std::getenv("TRICOT_CAMPAIGN_BARRIER_GROWTH")) o.barrier_growth = std::strtod(g, nullptr);
  // The material-stability barrier (ident/stability_barrier.hpp) unless TRICOT_CAMPAIGN_NO_BARRIER.
  if (std::getenv("TRICOT_CAMPAIGN_NO_BARRIER")) {
    run.result = ident::identify(*run.objective, o);
  } else {
    // TRICOT_CAMPAIGN_NO_ELLIPTICITY: the barrier without its strong-ellipticity rows.
    ident::StabilityBarrierOptions bo;
    if (std::getenv("TRICOT_CAMPAIGN_NO_ELLIPTICITY")) bo.acoustic_margin = 0;
    run.stabilized = std::make_unique<ident::StabilizedObjective>(*run.objective, bo);
    run.result = ident::identify(*run.stabilized, o);
  }
  run.start_errors = fit_errors;
  fem::ResponseSurface found = law;
  found.set_coefficients(run.result.parameters);
  run.errors = errors(c, found);
  return run;
}

double max_correlation(const ident::Uncertainty& u) {
  double m = 0;
  for (Eigen::Index i = 0; i < u.correlation.rows(); ++i)
    for (Eigen::Index j = 0; j < i; ++j)
      if (std::isfinite(u.correlation(i, j))) m = std::max(m, std::abs(u.correlation(i, j)));
  return m;
}

void report(benchmark::State& state, const Campaign& c, const Run& r, const std::string& label) {
  const auto& res = r.result;
  state.counters["objective"] = res.objective;
  state.counters["iterations"] = res.iterations;
  state.counters["evaluations"] = res.evaluations;
  state.counters["wall_s"] = res.wall_seconds;
  state.counters["condition"] = res.uncertainty.condition_number;
  state.counters["max_corr"] = max_correlation(res.uncertainty);
  state.counters["eq9_C_whole"] = r.errors.course.whole;
  state.counters["eq9_W_whole"] = r.errors.wale.whole;
  state.counters["eq9_C_pract"] = r.errors.course.practical;
  state.counters["eq9_W_pract"] = r.errors.wale.practical;
  state.counters["true_C_pract"] = r.errors.course_true.practical;
  state.counters["true_W_pract"] = r.errors.wale_true.practical;
  state.SetLabel(label + " " + ident::to_string(res.termination));
  std::printf("\n# %s: %s (%s)\n# f = %.4g, %d iterations, %d evaluations, %.1f s, cond %.3g, max |corr| %.3f\n",
              label.c_str(), ident::to_string(res.termination), res.message.c_str(), res.objective, res.iterations,
              res.evaluations, res.wall_seconds, res.uncertainty.condition_number, max_correlation(res.uncertainty));
  auto row = [](const char* what, const Surfaces& s) {
    std::printf("#   %-34s course %.3f / %.3f   wale %.3f / %.3f   (true: course %.3f / %.3f, wale %.3f / %.3f)\n",
                what, s.course.whole, s.course.practical, s.wale.whole, s.wale.practical, s.course_true.whole,
                s.course_true.practical, s.wale_true.whole, s.wale_true.practical);
  };
  std::printf(
      "#   eq. 9 whole / practical (points: course %d / %d, wale %d / %d); paper 110/14: course 0.218 / 0.084, wale "
      "0.313 / 0.079\n",
      r.errors.course.points_whole, r.errors.course.points_practical, r.errors.wale.points_whole,
      r.errors.wale.points_practical);
  row("LS fit of the points (no FE)", r.start_errors);
  row("identified (FE, field + force)", r.errors);
  std::printf("#   J*:");
  for (size_t k = 0; k < res.names.size(); ++k) std::printf(" %s=%.4g", res.names[k].c_str(), res.parameters(k));
  {
    fem::ResponseSurface law = fem::ResponseSurface::preset(res.names.size() == 14 ? "paper14" : "paper24", kShear);
    law.set_coefficients(res.parameters);
    double at_C = 0, at_W = 0;
    const double worst = smallest_stiffness(law, &at_C, &at_W);
    std::printf("\n#   smallest stiffness eigenvalue %.4g N/mm at (%.2f, %.2f)\n", worst, at_C, at_W);
    if (r.stabilized) {
      const auto A = r.stabilized->force_jacobians(res.parameters);
      size_t g_min = 0;
      for (size_t g = 0; g < A.size(); ++g)
        if (A[g].determinant() < A[g_min].determinant()) g_min = g;
      std::printf("#   smallest det dF/de %.4g (N/mm)^2 at (%.2f, %.2f); barrier part of f %.4g\n",
                  A[g_min].determinant(), r.stabilized->grid()[g_min](0), r.stabilized->grid()[g_min](1),
                  0.5 * r.stabilized->barrier(res.parameters).squaredNorm());
    }
  }
  // Identifiability at J* (only when LM ended at a point the FE solves with sensitivities).
  if (res.termination == ident::Termination::fe_failure) return;
  const ident::Evaluation e = r.objective->evaluate(res.parameters, true);
  std::fflush(stdout);
  if (!e.ok || e.jacobian.cols() != res.parameters.size()) {
    std::printf("#   no Jacobian at J* (%s; %td x %td)\n", e.message.c_str(), e.jacobian.rows(), e.jacobian.cols());
    return;
  }
  std::vector<std::vector<int>> rows(r.objective->experiment().tests.size());
  for (const auto& g : r.objective->data().groups())
    for (int i = 0; i < g.size; ++i) rows[g.test].push_back(g.offset + i);
  Eigen::VectorXd scale(res.parameters.size());
  for (Eigen::Index k = 0; k < scale.size(); ++k) scale(k) = r.objective->parameters()[k].resolved_scale();
  ident::IdentifiabilityOptions io;
  io.sigma2 = res.uncertainty.sigma2;
  const ident::IdentifiabilityReport id = ident::identifiability(e.jacobian, res.parameters, scale, rows, io);
  std::printf("#   coefficient   value        rel. std error  pinned\n");
  for (size_t k = 0; k < res.names.size(); ++k)
    std::printf("#   %-12s %12.5g  %10.3g      %s\n", res.names[k].c_str(), res.parameters(k), id.relative_std_error(k),
                id.pinned[k] ? "yes" : "no");
  std::printf("#   least identifiable direction:");
  for (Eigen::Index k = 0; k < id.least_identifiable.size(); ++k)
    if (std::abs(id.least_identifiable(k)) > 0.2)
      std::printf(" %+.2f %s", id.least_identifiable(k), res.names[k].c_str());
  std::printf("\n#   share of tr M / of the weak direction per test:");
  for (size_t t = 0; t < rows.size(); ++t)
    std::printf(" %s %.2f/%.2f", r.objective->experiment().tests[t].name.c_str(), id.trace_share[t],
                id.weak_direction_share[t]);
  std::printf("\n");
  (void)c;
}

void BM_Identify(benchmark::State& state, int size, std::string preset, bool restricted) {
  if (const char* spec = std::getenv("TRICOT_CAMPAIGN_PROBE")) {
    probe(spec);
    state.SkipWithError("probe only");
    return;
  }
  Campaign& c = campaign(size);
  for (auto _ : state) {
    Run r = identify(c, preset, restricted);
    state.SetIterationTime(r.result.wall_seconds);
    report(state, c, r, std::to_string(size) + "/" + preset + (restricted ? "/restricted" : ""));
  }
  state.counters["paper_ratio"] = 80 * 3600.0 / state.counters["wall_s"];  // the paper's ~80 h class
}

/// One evaluation of the 110 mm campaign at LM's start (paper14, the least-squares start), every test
/// with its 14 sensitivities, one thread: the unit of the identification's cost. Counters: Newton
/// iterations, factorizations and the factorization time per evaluation, per load step.
void BM_Evaluate(benchmark::State& state) {
  Campaign& c = campaign(110);
  fem::ResponseSurface law = fem::ResponseSurface::preset("paper14", kShear);
  law.set_coefficients(polynomial_start(law, c));
  fem::SolveOptions so;
  so.sensitivities = state.range(0) != 0;
  double newton = 0, factorizations = 0, factor_s = 0, steps = 0;
  for (auto _ : state) {
    newton = factorizations = factor_s = steps = 0;
    for (const auto& t : c.tests) {
      const fem::SimulationResult r = fem::simulate(t.model, law, so);
      if (!r.usable()) state.SkipWithError(r.message.c_str());
      for (const auto& s : r.steps) newton += s.iterations;
      factorizations += r.factorizations, factor_s += r.factorization_seconds;
      steps += static_cast<double>(r.steps.size());
    }
  }
  state.counters["steps"] = steps;
  state.counters["newton_per_step"] = newton / steps;
  state.counters["factorizations_per_step"] = factorizations / steps;
  state.counters["factor_ms_per_step"] = 1e3 * factor_s / steps;
}
BENCHMARK(BM_Evaluate)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

/// Issue 15, the paper's scale: one evaluation (field + grip force, 14 sensitivities) of the five
/// wale-pulled 110 mm tests × 21 steps with `paper14` at the slope start (a1 and c1 only, fitted to the
/// eq. 9 points: stable at every strain; the least-squares start and the 120-element J* both lose
/// material stability at the fine mesh's clip strains, docs/validation.md §9), on an nx × ny Q8 quarter (70 × 58: 24
/// 874 dofs, the paper's ~24 000), the data of the 24 × 20 synthesis, the tests on the objective's threads (OpenMP
/// default). The identification's cost is this times its evaluations.
void BM_EvaluatePaperScale(benchmark::State& state) {
  Campaign& c = campaign(110);
  fem::ResponseSurface law = fem::ResponseSurface::preset("paper14", kShear);
  const Eigen::VectorXd J0 = polynomial_start(law, c, 1);
  law.set_coefficients(J0);
  std::vector<fem::TestModel> models;
  ident::Experiment data;
  for (const auto& t : c.tests) {
    if (t.pull != fem::PullDirection::wale) continue;
    models.push_back(fem::make_rig_test(
        rig(c.spec, t.pull, t.transverse, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)))));
    data.tests.push_back(t.data);
  }
  std::vector<ident::Parameter> p;
  for (const std::string& name : law.coefficient_names()) p.push_back(ident::Parameter{name});
  const ident::Objective objective(models, data, law, p);
  for (auto _ : state) {
    const ident::Evaluation e = objective.evaluate(J0, true);
    if (!e.ok) state.SkipWithError(e.message.c_str());
  }
  state.counters["dofs"] = models.front().mesh.dofs();
  state.counters["tests"] = static_cast<double>(models.size());
}

/// Issue 15, the paper's scale as the paper checked it: "a biaxial test generated set of results",
/// 14 coefficients, a 24 000-dof mesh, ~80 h (§3, its ref. 24). The five wale-pulled 110 mm rig tests
/// × 21 steps, with the guides ending 5 % of the quarter's height short of the clips (the campaign's 15 %
/// gap leaves a free edge whose corner loses strong ellipticity on a fine mesh, under the reference
/// knit itself: docs/validation.md §9); their field (the campaign's
/// 3 × 3 points per quarter) and grip force generated on an nx × ny Q8 quarter by `paper14` at
/// kPaperScaleTruth. Cached per mesh: the synthesis is the experiment, not the identification.
const std::array<double, 14> kPaperScaleTruth{0.21808, 0.23574,  -0.14126, 0.024769,  0.017599, 0.0002448, 0.075506,
                                              0.10097, 0.049463, 0.076792, -0.080957, 0.11044,  0.10105,   0.085016};
struct PaperScale {
  std::vector<fem::TestModel> coarse, fine;  // the paper's 120 Q8 (12 × 10) and nx × ny
  ident::Experiment data;
  fem::ResponseSurface law = fem::ResponseSurface::preset("paper14", kShear);
  std::vector<ident::Parameter> parameters;  // LM's start: the 110 mm campaign's eq. 9 fit
};

PaperScale& paper_scale(int nx, int ny) {
  static std::map<std::pair<int, int>, PaperScale> cache;
  auto it = cache.find({nx, ny});
  if (it != cache.end()) return it->second;
  PaperScale ps;
  const Eigen::VectorXd J_fit = polynomial_start(ps.law, campaign(110));
  ps.law.set_coefficients(Eigen::Map<const Eigen::VectorXd>(kPaperScaleTruth.data(), 14));
  const auto t0 = std::chrono::steady_clock::now();
  const std::pair<fem::PullDirection, double> tests[] = {{fem::PullDirection::wale, 0},
                                                         {fem::PullDirection::wale, 0.4},
                                                         {fem::PullDirection::wale, 0.7},
                                                         {fem::PullDirection::course, 0},
                                                         {fem::PullDirection::course, 0.3}};
  for (const auto& [pull, x] : tests) {
    fem::RigOptions o = rig(k110, pull, x, 12, 10);
    o.guide_gap = 0.05;
    ps.coarse.push_back(fem::make_rig_test(o));
    o.nx = nx, o.ny = ny;
    ps.fine.push_back(fem::make_rig_test(o));
  }
  ps.data.tests.resize(ps.fine.size());
  std::vector<fem::StrainSpread> spread(ps.fine.size());
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i; (i = next++) < ps.fine.size();) {
      const fem::SimulationResult r = fem::simulate(ps.fine[i], ps.law);
      if (!r.usable()) throw std::runtime_error(r.message);
      Eigen::Matrix2Xd points(2, 9);
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) points.col(3 * j + k) = Eigen::Vector2d(9 + 18 * k, 9 + 18 * j);
      ps.data.tests[i] = ident::measure(ps.fine[i], r, points);
      spread[i] = fem::strain_spread(ps.fine[i], r.steps.back().u);
    }
  };
  std::thread helper(work);
  work();
  helper.join();
  std::printf("\n# paper scale: %zu tests x %d steps on %d x %d Q8 (%d dofs), generated by paper14 in %.1f s\n",
              ps.fine.size(), k110.steps, nx, ny, ps.fine.front().mesh.dofs(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  for (size_t i = 0; i < ps.fine.size(); ++i)
    std::printf("# %-12s eC [%6.3f, %6.3f]  eW [%6.3f, %6.3f]  centre (%.3f, %.3f)\n", ps.fine[i].name.c_str(),
                spread[i].eC_min, spread[i].eC_max, spread[i].eW_min, spread[i].eW_max, spread[i].eC_centre,
                spread[i].eW_centre);
  const auto names = ps.law.coefficient_names();
  for (size_t k = 0; k < names.size(); ++k) {
    ident::Parameter q;  // as identify() above: the campaign's start, scales and bounds
    q.name = names[k], q.start = J_fit(static_cast<Eigen::Index>(k));
    q.scale = std::max(std::abs(q.start), 1e-3);
    if (q.name == "a6" || q.name == "c4") q.lower = 0, q.start = std::max(q.start, 0.0);
    ps.parameters.push_back(q);
  }
  return cache.emplace(std::make_pair(nx, ny), std::move(ps)).first->second;
}

/// The paper-scale identification, from the campaign's eq. 9 fit, by mesh levels
/// (ident::identify_by_levels; range(2) = 1: LM on the 120 Q8 with the stability test, then nx × ny
/// through the 120 Q8 corrected to it), or LM on nx × ny alone (0; at 70 × 58 that takes tens of
/// minutes, so it is not run by `make bench`), the objectives warm started. Counters: wall time, iterations and FE
/// evaluations of each level, the coarse evaluations inside the corrected models, f, the largest relative error of a
/// coefficient against the truth (absolute where the truth is 0), the paper's ~80 h over the wall time.
void BM_IdentifyPaperScale(benchmark::State& state) {
  PaperScale& ps = paper_scale(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  ident::ObjectiveOptions oo;
  oo.sensitivities_after = true;                // as a project with bounds
  oo.warm_start = !std::getenv("TRICOT_COLD");  // TRICOT_COLD: every evaluation from the load path
  ident::IdentifyOptions o;
  o.initial_trust_region_radius = 100, o.line_search_trials = 4, o.active_set = true;  // project-110.toml
  if (const char* g = std::getenv("TRICOT_CAMPAIGN_BARRIER_GROWTH")) o.barrier_growth = std::strtod(g, nullptr);
  const ident::Objective coarse(ps.coarse, ps.data, ps.law, ps.parameters, oo),
      fine(ps.fine, ps.data, ps.law, ps.parameters, oo);
  const ident::StabilizedObjective coarse_s(coarse), fine_s(fine);
  std::vector<const ident::Problem*> levels{&fine_s};
  if (state.range(2)) levels.insert(levels.begin(), &coarse_s);
  ident::LevelsResult r;
  Reporter progress;  // LM's iterations on stderr, with the time since the start
  const auto t0 = std::chrono::steady_clock::now();
  progress.progress = [&](const Progress& p) {
    std::fprintf(stderr, "# %6.1f s  %s %zu: %s\n",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), p.stage.c_str(), p.done,
                 p.detail.substr(0, 60).c_str());
  };
  for (auto _ : state) {
    r = ident::identify_by_levels(levels, o, progress);
    state.SetIterationTime(r.wall_seconds);
  }
  const Eigen::Map<const Eigen::VectorXd> truth(kPaperScaleTruth.data(), 14);
  double worst = 0;
  for (Eigen::Index k = 0; k < truth.size(); ++k)
    worst = std::max(worst, std::abs(r.result.parameters(k) - truth(k)) / (truth(k) != 0 ? std::abs(truth(k)) : 1.0));
  for (size_t l = 0; l < r.levels.size(); ++l) {
    const ident::IdentifyResult& x = r.levels[l];
    const auto& models = levels[l] == &fine_s ? ps.fine : ps.coarse;
    std::printf("# level %zu (%d dofs): %s\n#   J:", l, models.front().mesh.dofs(), x.brief_report().c_str());
    for (Eigen::Index k = 0; k < x.parameters.size(); ++k) std::printf(" %.5g", x.parameters(k));
    std::printf("\n");
    std::fflush(stdout);
    const std::string tag = "L" + std::to_string(l) + "_";
    state.counters[tag + "wall_s"] = x.wall_seconds;
    state.counters[tag + "evals"] = x.evaluations;
    state.counters[tag + "iter"] = x.iterations;
  }
  state.counters["coarse_evals"] = r.coarse_evaluations;  // the first level's, in the corrected models
  state.counters["objective"] = r.result.objective;
  state.counters["barrier_at_truth"] = fine_s.lower_bound(truth);  // f's floor: the truth's barrier part
  state.counters["max_rel_err"] = worst;
  state.counters["dofs"] = ps.fine.front().mesh.dofs();
  state.counters["paper_ratio"] = 80 * 3600.0 / r.wall_seconds;
  state.SetLabel(ident::to_string(r.result.termination));
}
/// The evaluation an identification makes next (issue 15): the paper-scale fixture's five tests on
/// nx × ny with their 14 sensitivities, at the truth × 1.01, after an untimed one at the truth; cold
/// (range(2) = 0) or warm started from it (1: ObjectiveOptions::warm_start).
void BM_EvaluateNextPaperScale(benchmark::State& state) {
  PaperScale& ps = paper_scale(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  ident::ObjectiveOptions oo;
  oo.warm_start = state.range(2) != 0;
  const ident::Objective objective(ps.fine, ps.data, ps.law, ps.parameters, oo);
  const Eigen::Map<const Eigen::VectorXd> truth(kPaperScaleTruth.data(), 14);
  for (auto _ : state) {
    state.PauseTiming();
    const ident::Evaluation before = objective.evaluate(truth, true);
    if (!before.ok) state.SkipWithError(before.message.c_str());
    state.ResumeTiming();
    const ident::Evaluation e = objective.evaluate(1.01 * truth, true);
    if (!e.ok) state.SkipWithError(e.message.c_str());
  }
}
BENCHMARK(BM_EvaluateNextPaperScale)
    ->Args({70, 58, 0})
    ->Args({70, 58, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

BENCHMARK(BM_IdentifyPaperScale)
    ->Args({70, 58, 1})
    ->Args({24, 20, 1})
    ->Args({24, 20, 0})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

BENCHMARK(BM_EvaluatePaperScale)
    ->Args({12, 10})
    ->Args({70, 58})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

BENCHMARK_CAPTURE(BM_Identify, 110 / paper14, 110, "paper14", false)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Identify, 110 / paper14 / restricted, 110, "paper14", true)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Identify, 110 / paper24, 110, "paper24", false)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Identify, 150 / paper14, 150, "paper14", false)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_Identify, 150 / paper24, 150, "paper24", false)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

}  // namespace
