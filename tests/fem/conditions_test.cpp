// Models of any mesh (docs/theory.md §6): conditions per named boundary and component, series per step that
// load, hold and unload, boundary resultants, and their exact sensitivities, on T3, T6, Q4 and Q8.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "testing/newton.hpp"
#include "testing/record.hpp"
#include "testing_law.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/mesh.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/neo_hookean.hpp"
#include "tricot/fem/solver.hpp"

namespace tricot::fem {
namespace {

constexpr double kSame = 1e-10;         // two formulations of one model: Newton's tolerance apart at most
constexpr double kPatch = 1e-10;        // a homogeneous state is reproduced to round-off
constexpr double kTightNewton = 1e-13;  // runs that are differenced
constexpr double kFdSimulate = 1e-7;    // issue 28: sensitivities within 1e-7 of central differences

using test::record;

Mesh quarter(ElementType type, int nx, int ny, double width, double height) {
  MeshOptions o;
  o.type = type, o.nx = nx, o.ny = ny, o.width = width, o.height = height;
  return make_quarter_mesh(o);
}

SolveOptions tight() {
  SolveOptions o;
  o.tolerance = kTightNewton;
  return o;
}

// The full strip [−W, W] × [−H, H]: the quarter generator's mesh moved to the centre, its bottom fixed
// along y, one bottom node also along x, its top pulled by `top` (one value per step).
TestModel full_strip(ElementType type, std::vector<double> top, double W = 10, double H = 25) {
  TestModel t;
  t.name = "full";
  t.mesh = quarter(type, 4, 6, 2 * W, 2 * H);
  t.mesh.X.row(0).array() -= W;
  t.mesh.X.row(1).array() -= H;
  t.mesh.boundaries["anchor"] = {t.mesh.bottom.front()};
  t.loads.resize(top.size());
  for (size_t k = 0; k < top.size(); ++k) t.loads[k] = static_cast<double>(k + 1);
  t.conditions = {{"bottom", 1, {}}, {"anchor", 0, {}}, {"top", 1, std::move(top)}};
  t.force_boundary = "top";
  return t;
}

// P22 of the uniaxial state F = diag(λ1, λ2) with P11 = 0 (λ1 by Newton).
double uniaxial_P22(const Law& law, double l2, double& l1) {
  LawInput in;
  LawOutput o;
  l1 = 1;
  for (int it = 0; it < 60; ++it) {
    in.F << l1, 0, 0, l2;
    law.evaluate(in, {}, o);
    l1 -= o.P(0, 0) / o.A(0, 0);
  }
  in.F << l1, 0, 0, l2;
  law.evaluate(in, {}, o);
  return o.P(1, 1);
}

class AnyElement : public ::testing::TestWithParam<ElementType> {};

TEST_P(AnyElement, AFullStripPulledByItsTopIsHomogeneousWithTheForceAsItsResultant) {
  const test::TestingLaw law(1.0, 2.0, 0.5);
  const double W = 10, H = 25, d = 8;
  const TestModel t = full_strip(GetParam(), {d / 2, d});
  const SimulationResult r = simulate(t, law, tight());
  ASSERT_TRUE(r.usable()) << r.message;
  double l1 = 1;
  const double P22 = uniaxial_P22(law, 1 + d / (2 * H), l1);
  const StepResult& last = r.steps.back();
  double worst = 0;  // distance from x = (λ1 (X + W) − W, λ2 (Y + H) − H) with the anchor at (−W, −H)
  for (int n = 0; n < t.mesh.nodes(); ++n) {
    const Vec2 X = t.mesh.X.col(n);
    const Vec2 u((l1 - 1) * (X(0) + W), (d / (2 * H)) * (X(1) + H));
    worst = std::max(worst, (last.u.segment<2>(2 * n) - u).norm());
  }
  record(std::string("full_patch_error_") + to_string(GetParam()), worst / d);
  EXPECT_LT(worst, kPatch * d);
  EXPECT_NEAR(last.edge_force, P22 * 2 * W, kPatch * P22 * 2 * W);
  EXPECT_DOUBLE_EQ(last.edge_displacement, d);
  // Resultants of the named boundaries: the top carries +F along y, the bottom −F, the anchor 0 along x.
  ASSERT_EQ(last.resultants.size(), 3u);  // bottom, anchor, top: the order of the conditions
  EXPECT_NEAR(last.resultants[2].y(), last.edge_force, kPatch * last.edge_force);
  EXPECT_NEAR(last.resultants[0].y(), -last.edge_force, kPatch * last.edge_force);
  EXPECT_NEAR(last.resultants[2].x(), 0, kPatch * last.edge_force);
}

TEST_P(AnyElement, SensitivitiesOfTheResultantAndTheFieldMatchCentralDifferencesWithTiedSides) {
  TestModel t = full_strip(GetParam(), {3, 6, 4});           // load, then partly unload
  t.conditions.push_back({"right", 0, {-0.5, -1.0, -0.8}});  // and squeeze the side through ties
  t.conditions.back().tie = 0.3;                             // ending 20 mm short of the top,
  t.conditions.back().tie_end = Vec2(t.mesh.X.row(0).maxCoeff(), t.mesh.X.row(1).maxCoeff() - 20);
  t.conditions.back().tie_taper = 10;  // tapered
  t.material_angle = 20;
  test::TestingLaw law(1.0, 2.0, 0.5);
  SolveOptions o = tight();
  o.sensitivities = true;
  const SimulationResult r = simulate(t, law, o);
  ASSERT_TRUE(r.usable()) << r.message;
  const Eigen::VectorXd c = law.coefficients();
  double worst_u = 0, worst_f = 0;
  for (Eigen::Index k = 0; k < c.size(); ++k) {
    const double h = 1e-6 * std::max(1.0, std::abs(c(k)));
    auto run = [&](double dc) {
      test::TestingLaw l = law;
      Eigen::VectorXd cc = c;
      cc(k) += dc;
      l.set_coefficients(cc);
      return simulate(t, l, tight());
    };
    const SimulationResult plus = run(h), minus = run(-h);
    ASSERT_TRUE(plus.usable() && minus.usable());
    for (size_t s = 0; s < r.steps.size(); ++s) {
      const Eigen::VectorXd du = (plus.steps[s].u - minus.steps[s].u) / (2 * h);
      worst_u = std::max(worst_u, (r.steps[s].du_dc.col(k) - du).norm() / std::max(du.norm(), 1e-12));
      const double df = (plus.steps[s].edge_force - minus.steps[s].edge_force) / (2 * h);
      worst_f = std::max(worst_f, std::abs(r.steps[s].dforce_dc(k) - df) / std::max(std::abs(df), 1e-12));
    }
  }
  record(std::string("conditions_du_fd_error_") + to_string(GetParam()), worst_u);
  record(std::string("conditions_force_fd_error_") + to_string(GetParam()), worst_f);
  EXPECT_LT(worst_u, kFdSimulate);
  EXPECT_LT(worst_f, kFdSimulate);
}

INSTANTIATE_TEST_SUITE_P(AllTypes, AnyElement,
                         ::testing::Values(ElementType::T3, ElementType::T6, ElementType::Q4, ElementType::Q8),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST(Conditions, TheQuarterModelWrittenAsNamedConditionsGivesTheBuiltInAnswer) {
  // The built-in quarter (symmetry on left and bottom, a clamped grip, a rigid guide) and the same
  // mesh with those conditions named: the same states and grip force to Newton's tolerance.
  const test::TestingLaw law(1.0, 2.0, 0.5);
  TestModel built_in;
  built_in.name = "quarter";
  built_in.mesh = quarter(ElementType::Q8, 4, 6, 10, 25);
  built_in.material_angle = 30;
  built_in.loads = {2, 4, 6};
  built_in.side = SideEdge::guide;
  built_in.guide = {-0.5, -1.0, -1.5};
  TestModel named = built_in;
  named.side = SideEdge::free;
  named.guide.clear();
  named.conditions = {
      {"left", 0, {}}, {"bottom", 1, {}}, {"top", 0, {}}, {"top", 1, {2, 4, 6}}, {"right", 0, {-0.5, -1.0, -1.5}}};
  named.force_boundary = "top";
  named.force_scale = 2;  // the quarter's grip carries half the specimen's force
  const SimulationResult a = simulate(built_in, law, tight()), b = simulate(named, law, tight());
  ASSERT_TRUE(a.usable() && b.usable()) << a.message << b.message;
  for (size_t k = 0; k < a.steps.size(); ++k) {
    EXPECT_LT((a.steps[k].u - b.steps[k].u).cwiseAbs().maxCoeff(), kSame * a.steps[k].u.cwiseAbs().maxCoeff());
    EXPECT_NEAR(a.steps[k].edge_force, b.steps[k].edge_force, kSame * std::abs(a.steps[k].edge_force));
    EXPECT_DOUBLE_EQ(a.steps[k].edge_displacement, b.steps[k].edge_displacement);
  }
}

TEST(Conditions, ALoadHoldUnloadSeriesReturnsToTheSameStatesOnTheWayBack) {
  // Hyperelastic: the state depends on the prescribed displacement only. Loading to 6, holding and
  // unloading to 3 and to 0 meets the loading states again, and ends unloaded.
  const test::TestingLaw law(1.0, 2.0, 0.5);
  const SimulationResult r = simulate(full_strip(ElementType::T6, {3, 6, 6, 3, 0}), law, tight());
  ASSERT_TRUE(r.usable()) << r.message;
  const auto& s = r.steps;
  EXPECT_NEAR(s[3].edge_force, s[0].edge_force, kSame * s[1].edge_force);
  EXPECT_NEAR(s[2].edge_force, s[1].edge_force, kSame * s[1].edge_force);
  EXPECT_LT((s[3].u - s[0].u).cwiseAbs().maxCoeff(), kSame * s[1].u.cwiseAbs().maxCoeff());
  EXPECT_LT(s[4].u.cwiseAbs().maxCoeff(), kSame * s[1].u.cwiseAbs().maxCoeff());
  EXPECT_NEAR(s[4].edge_force, 0, kSame * s[1].edge_force);
}

TEST(Conditions, NewtonConvergesQuadraticallyOnAClampedFullT6Strip) {
  // The full strip clamped at both ends (both components held at the bottom, the top pulled along y
  // and held along x) in one step to 40 % strain with the paper's Mooney–Rivlin law: the clamps make
  // the field inhomogeneous. Every contraction above round-off is quadratic, r_k+1 ≤ C r_k², and the
  // order from the last three residuals above round-off is ≥ 1.9.
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  TestModel t = full_strip(ElementType::T6, {20});
  t.conditions = {{"bottom", 0, {}}, {"bottom", 1, {}}, {"top", 0, {}}, {"top", 1, {20}}};
  SolveOptions o = tight();
  o.max_cutbacks = 0;  // one Newton run: its whole history is kept
  const SimulationResult r = simulate(t, law, o);
  ASSERT_TRUE(r.usable()) << r.message;
  const std::vector<double>& res = r.steps.back().residuals;
  std::string history;
  for (double x : res) history += std::to_string(x) + " ";
  const double floor = 1e-11 * res.front();
  constexpr double kQuadraticConstant = 20;  // 1/N: a linear rate of 0.1 would break it below 5e-3 N
  for (size_t i = 1; i < res.size(); ++i)
    if (res[i] > floor) {
      EXPECT_LE(res[i], kQuadraticConstant * res[i - 1] * res[i - 1]) << history;
    }
  const double p = test::convergence_order(res, floor);
  record("newton_order_T6", p);
  EXPECT_GE(p, 1.9) << history;
}

TEST(Conditions, PlaneStrainNeoHookeanPulledBetweenHeldSidesGivesTheClosedForm) {
  // F = diag(1, λ) (sides held, u_x = 0 on left and right): P22 = μ (λ − 1/λ) + λ_L ln λ / λ.
  const double mu = 0.8, lam = 2.5, W = 10, H = 25, d = 10;
  const NeoHookean law(mu, lam, Kinematics::plane_strain);
  TestModel t = full_strip(ElementType::T6, {d});
  t.conditions.push_back({"left", 0, {}});
  t.conditions.push_back({"right", 0, {}});
  const SimulationResult r = simulate(t, law, tight());
  ASSERT_TRUE(r.usable()) << r.message;
  const double l = 1 + d / (2 * H);
  const double P22 = mu * (l - 1 / l) + lam * std::log(l) / l;
  EXPECT_NEAR(r.steps.back().edge_force, P22 * 2 * W, kPatch * P22 * 2 * W);
}

TEST(Conditions, AnUnknownBoundaryIsNamedWithADidYouMean) {
  TestModel t = full_strip(ElementType::T3, {1});
  t.conditions[2].boundary = "tpo";
  try {
    t.validate();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "test.conditions[2].boundary");
    EXPECT_NE(std::string(e.what()).find("did you mean 'top'?"), std::string::npos) << e.what();
  }
}

TEST(Conditions, ASeriesShorterThanTheStepsIsRefused) {
  TestModel t = full_strip(ElementType::T3, {1, 2, 3});
  t.conditions[2].values = {1, 2};
  try {
    t.validate();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "test.conditions[2].values");
    EXPECT_NE(std::string(e.what()).find("2 values for 3 steps"), std::string::npos) << e.what();
  }
}

TEST(Conditions, TheQuarterGuideAndNamedConditionsDoNotMix) {
  TestModel t = full_strip(ElementType::T3, {1});
  t.side = SideEdge::guide;
  t.guide = {1};
  EXPECT_THROW(t.validate(), InputError);
}

}  // namespace
}  // namespace tricot::fem
