#include "tricot/fem/solver.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <map>
#include <random>
#include <sstream>

#include "assembly.hpp"  // white-box: the global residual and tangent
#include "testing/fd_check.hpp"
#include "testing/newton.hpp"
#include "testing/record.hpp"
#include "testing_law.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/reference_fabric.hpp"

namespace tricot::fem {
namespace {

constexpr double kPatch = 1e-10;        // issue 2: a uniform strain is reproduced to 1e-10
constexpr double kFdTangent = 1e-6;     // central differences, h = 1e-6: round-off ~1e-10 of the entries
constexpr double kFdSimulate = 1e-5;    // brief: sensitivities match FD of whole simulations to 1e-5
constexpr double kTightNewton = 1e-13;  // Newton tolerance for runs that are differenced
constexpr double kRoundOff = 1e-12;     // residual floor / grip force: round-off ends ≤ 5e-15 × the force

using test::record;

Mesh strip(ElementType type, int nx, int ny, double width = 10, double height = 25) {
  MeshOptions o;
  o.type = type, o.nx = nx, o.ny = ny, o.width = width, o.height = height;
  return make_quarter_mesh(o);
}

// Interior and edge nodes moved at random (edge nodes along their edge, corners fixed), by up to
// 20 % of the element size: elements become general (and, for Q8, curved) quadrilaterals.
Mesh distort(Mesh m, double hx, double hy) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> r(-0.2, 0.2);
  const double W = m.X.row(0).maxCoeff(), H = m.X.row(1).maxCoeff();
  for (int n = 0; n < m.nodes(); ++n) {
    const double x = m.X(0, n), y = m.X(1, n);
    const bool on_x = x == 0 || x == W, on_y = y == 0 || y == H;
    if (!on_x) m.X(0, n) += r(rng) * hx;
    if (!on_y) m.X(1, n) += r(rng) * hy;
  }
  return m;
}

TestModel model(Mesh mesh, std::vector<double> loads) {
  TestModel t;
  t.name = "t";
  t.mesh = std::move(mesh);
  t.loads = std::move(loads);
  return t;
}

SolveOptions tight() {
  SolveOptions o;
  o.tolerance = kTightNewton;
  return o;
}

// The homogeneous uniaxial state of the test law: lateral stretch λ2 with P11(diag(λ2, λ)) = 0.
struct Uniform {
  double l1, l2, P22, P11;
};
Uniform uniform_state(const Law& law, double l2_given, double l1_fixed = NAN) {
  auto P = [&](double a, double b) {
    LawInput in;
    in.F << a, 0, 0, b;
    LawOutput o;
    law.evaluate(in, {}, o);
    return o;
  };
  double l1 = std::isnan(l1_fixed) ? 1.0 : l1_fixed;
  if (std::isnan(l1_fixed))
    for (int it = 0; it < 50; ++it) {
      const LawOutput o = P(l1, l2_given);
      l1 -= o.P(0, 0) / o.A(0, 0);
    }
  const LawOutput o = P(l1, l2_given);
  return {l1, l2_given, o.P(1, 1), o.P(0, 0)};
}

// The largest distance of a node from its place in the homogeneous state x = (λ1 X, λ2 Y).
double distance_from_uniform(const StepResult& step, const Mesh& mesh, const Uniform& s) {
  double worst = 0;
  for (int n = 0; n < mesh.nodes(); ++n) {
    const Vec2 X = mesh.X.col(n);
    worst = std::max(worst, (step.u.segment<2>(2 * n) - Vec2((s.l1 - 1) * X(0), (s.l2 - 1) * X(1))).norm());
  }
  return worst;
}

// ---------------------------------------------------------------------------------------------------

class Types : public ::testing::TestWithParam<ElementType> {};

TEST_P(Types, PatchTestReproducesUniformUniaxialStrainOnADistortedMesh) {
  const test::TestingLaw law(1.0, 2.0);
  const double W = 10, H = 25, d = 10;
  TestModel t = model(distort(strip(GetParam(), 3, 4, W, H), W / 3, H / 4), {4, d});
  t.grip_holds_x = false;  // sliding grip, free side: the exact field is homogeneous
  const SimulationResult r = simulate(t, law, tight());
  ASSERT_TRUE(r.usable()) << r.message;
  const Uniform s = uniform_state(law, 1 + d / H);
  const StepResult& last = r.steps.back();
  const double err = distance_from_uniform(last, t.mesh, s) / d;
  record(std::string("patch_error_") + to_string(GetParam()), err);
  EXPECT_LT(err, kPatch);
  EXPECT_NEAR(last.edge_force, s.P22 * 2 * W, kPatch * std::abs(s.P22 * 2 * W));
  EXPECT_NEAR(last.force_per_width, s.P22, kPatch * std::abs(s.P22));
  EXPECT_DOUBLE_EQ(last.edge_displacement, d);
  EXPECT_EQ(last.side_force, 0);
}

// A distorted mesh with a guide u_x = c on the side edge reproduces the homogeneous biaxial state:
// node positions, the grip force and the side force.
void expect_guided_patch(ElementType type, double c, bool clamp_follows_guide) {
  const test::TestingLaw law(1.0, 2.0, 0.5);
  const double W = 10, H = 25, d = 5;
  TestModel t = model(distort(strip(type, 3, 4, W, H), W / 3, H / 4), {2, d});
  t.grip_holds_x = clamp_follows_guide;  // else a sliding grip
  t.grip_follows_guide = clamp_follows_guide;
  t.side = SideEdge::guide;
  t.guide = {c};
  const SimulationResult r = simulate(t, law, tight());
  ASSERT_TRUE(r.usable()) << r.message;
  const Uniform s = uniform_state(law, 1 + d / H, 1 + c / W);
  const StepResult& last = r.steps.back();
  EXPECT_LT(distance_from_uniform(last, t.mesh, s), kPatch * d);
  EXPECT_NEAR(last.edge_force, s.P22 * 2 * W, kPatch * std::abs(s.P22 * W));
  EXPECT_NEAR(last.side_force, s.P11 * 2 * H, kPatch * std::abs(s.P22 * W));
}

TEST_P(Types, PatchTestWithAGuideGivesTheSideForce) { expect_guided_patch(GetParam(), -2, false); }

TEST_P(Types, ForceControlledPatchTestKeepsTheGripStraight) {
  const test::TestingLaw law(1.0, 2.0);
  const double W = 10, H = 25;
  TestModel t = model(distort(strip(GetParam(), 3, 4, W, H), W / 3, H / 4), {2, 6});
  t.grip_holds_x = false;
  t.control = GripControl::force;
  const SimulationResult r = simulate(t, law, tight());
  ASSERT_TRUE(r.usable()) << r.message;
  const StepResult& last = r.steps.back();
  const Uniform s = uniform_state(law, 1 + last.edge_displacement / H);
  EXPECT_NEAR(s.P22 * 2 * W, 6, kPatch * 6);  // the found stretch carries the prescribed force
  EXPECT_NEAR(last.edge_force, 6, kPatch * 6);
  EXPECT_LT(distance_from_uniform(last, t.mesh, s), kPatch * H);
}

TEST_P(Types, PatchTestWithAClampThatFollowsTheGuideIsHomogeneous) {
  // A clamp whose width opens with the guide (u_x = c·X/W on the grip) agrees with the homogeneous
  // biaxial state, so a distorted mesh must reproduce it (docs/theory.md §6).
  expect_guided_patch(GetParam(), 3, true);
}

INSTANTIATE_TEST_SUITE_P(Q4AndQ8, Types, ::testing::Values(ElementType::Q4, ElementType::Q8),
                         [](const auto& info) { return std::string(to_string(info.param)); });
INSTANTIATE_TEST_SUITE_P(T3AndT6, Types, ::testing::Values(ElementType::T3, ElementType::T6),
                         [](const auto& info) { return std::string(to_string(info.param)); });

// ---------------------------------------------------------------------------------------------------

// The free residual R_f(z) and its tangent, through the solver's own assembly.
struct Global {
  TestModel t;
  detail::DofMap dofs;
  std::unique_ptr<detail::Assembler> assembler;
  explicit Global(TestModel m, const Law& law) : t(std::move(m)), dofs(detail::make_dof_map(t)) {
    assembler = std::make_unique<detail::Assembler>(t, dofs, law);
  }
  detail::Assembled at(const Eigen::VectorXd& z, const detail::Load& L) const {
    Eigen::VectorXd u;
    detail::expand(dofs, z, L, u);
    detail::Assembled a;
    EXPECT_TRUE(assembler->assemble(u, {true, true}, a))
        << int(a.status) << " element " << a.element << " detF " << a.min_detF;
    return a;
  }
  Eigen::VectorXd residual(const Eigen::VectorXd& z, const detail::Load& L) const {
    const detail::Assembled a = at(z, L);
    Eigen::VectorXd R = Eigen::VectorXd::Zero(dofs.equations);
    for (size_t k = 0; k < dofs.eq.size(); ++k)
      if (dofs.eq[k] >= 0) R(dofs.eq[k]) += a.f(k);
    if (dofs.master >= 0) R(dofs.master) -= 0.5 * L.F;
    return R;
  }
};

TEST(GlobalTangent, MatchesFiniteDifferencesOfTheResidual) {
  const test::TestingLaw law(1.0, 2.0, 0.6);
  for (int config = 0; config < 3; ++config) {
    const GripControl control = config == 1 ? GripControl::force : GripControl::displacement;
    TestModel t = model(distort(strip(ElementType::Q8, 2, 3, 10, 15), 5, 5), {1});
    t.control = control;
    t.side = SideEdge::guide;
    t.guide = {-1};
    t.grip_follows_guide = config == 2;  // the guide also moves the clamp: ∂R/∂c has X/W weights
    t.material_angle = 30;
    const Global g(t, law);
    // A smooth non-uniform field plus noise, on the free dofs.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> r(-0.05, 0.05);
    Eigen::VectorXd z(g.dofs.equations);
    for (size_t k = 0; k < g.dofs.eq.size(); ++k) {
      const Vec2 X = g.t.mesh.X.col(k / 2);
      if (g.dofs.eq[k] >= 0) z(g.dofs.eq[k]) = (k % 2 ? 0.1 * X(1) + 0.01 * X(0) * X(1) : -0.05 * X(0)) + r(rng);
    }
    const detail::Load L{2.0, 0.5, -1.0};
    const detail::Assembled a = g.at(z, L);
    auto R = [&](const Eigen::VectorXd& zz) -> Eigen::VectorXd { return g.residual(zz, L); };
    const Eigen::MatrixXd K = a.K;
    const double err = test::jacobian_error(R, z, K);
    record(config == 1 ? "global_tangent_fd_error_force"
                       : (config == 2 ? "global_tangent_fd_error_pantograph" : "global_tangent_fd_error_displacement"),
           err);
    EXPECT_TRUE(test::JacobianMatches(R, z, K, kFdTangent));
    // ∂R_f/∂c of the guide and ∂(Σ_top f_y)/∂z, used by the predictor and the force sensitivity.
    auto R_of_c = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd { return g.residual(z, {L.d, L.F, c(0)}); };
    EXPECT_TRUE(
        test::JacobianMatches(R_of_c, Eigen::VectorXd::Constant(1, L.c), Eigen::MatrixXd(a.g_guide), kFdTangent));
    auto top = [&](const Eigen::VectorXd& zz) -> Eigen::VectorXd {
      const detail::Assembled b = g.at(zz, L);
      double s = 0;
      for (int k : g.dofs.top_y) s += b.f(k);
      return Eigen::VectorXd::Constant(1, s);
    };
    EXPECT_TRUE(test::JacobianMatches(top, z, Eigen::MatrixXd(a.h_top.transpose()), kFdTangent));
    if (control == GripControl::displacement) {
      auto R_of_d = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd { return g.residual(z, {d(0), 0, L.c}); };
      EXPECT_TRUE(
          test::JacobianMatches(R_of_d, Eigen::VectorXd::Constant(1, L.d), Eigen::MatrixXd(a.g_grip), kFdTangent));
    }
  }
}

// ---------------------------------------------------------------------------------------------------

TEST(Newton, ConvergesQuadraticallyOnAClampedStrip) {
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  TestModel t = model(strip(ElementType::Q8, 4, 8, 10, 25), {10});  // one step to 40 % strain, clamped
  SolveOptions o;
  o.tolerance = 1e-13;
  o.max_cutbacks = 0;  // one Newton run: its whole history is kept
  const SimulationResult ok = simulate(t, law, o);
  ASSERT_TRUE(ok.usable()) << ok.message;
  const std::vector<double>& res = ok.steps[0].residuals;
  ASSERT_GE(res.size(), 4u);
  // Order from the last three residuals well above round-off (1e-9 of the first).
  const double p = test::convergence_order(res, 1e-9 * res[0]);
  ASSERT_FALSE(std::isnan(p));
  record("newton_order", p);
  std::ostringstream hist;
  for (double x : res) hist << x << " ";
  RecordProperty("newton_residual_history", hist.str());
  EXPECT_GE(p, 1.8) << hist.str();
}

TEST(Newton, ConvergesQuadraticallyOnAClampedBiaxialFabricTest) {
  // The biaxial-fabric example's specimen and steps (quarter 55 × 55 mm², 10 × 12 Q8, 21 steps to a
  // 40 mm grip displacement, loaded along the course) with a clamp that keeps its width (u_x = 0) and a
  // guide opened to 3 mm: the clamp and the guide disagree at the corner, so the field is not
  // homogeneous (a 4 mm guide inverts the corner element at step 19). Tangent not symmetric: LU.
  const ReferenceFabric law;
  MeshOptions m;
  m.width = m.height = 55, m.nx = 10, m.ny = 12;
  TestModel t = model(make_quarter_mesh(m), {});
  // 5 steps: with 21 the predictor leaves Newton two iterations, too few to measure an order.
  for (int k = 1; k <= 5; ++k) t.loads.push_back(40.0 * k / 5);
  t.side = SideEdge::guide;
  t.guide = {3};
  t.material_angle = 90;
  const SimulationResult r = simulate(t, law);
  ASSERT_TRUE(r.usable()) << r.message;
  ASSERT_EQ(r.steps.size(), 5u);
  int checked = 0;
  std::ostringstream table;
  for (size_t k = 0; k < r.steps.size(); ++k) {
    const StepResult& s = r.steps[k];
    EXPECT_EQ(s.cutbacks, 0) << "step " << k + 1;
    table << "step " << k + 1 << ":";
    for (double x : s.residuals) table << " " << x;
    table << "; ";
    // Every contraction above round-off is quadratic: r_k+1 ≤ C r_k² (measured C ≤ 7 /N here).
    constexpr double kQuadraticConstant = 20;  // 1/N; a linear rate 0.1 would break it below r = 5e-3 N
    const double floor = kRoundOff * std::abs(s.edge_force);
    for (size_t i = 1; i < s.residuals.size(); ++i)
      if (s.residuals[i] > floor) {
        EXPECT_LE(s.residuals[i], kQuadraticConstant * s.residuals[i - 1] * s.residuals[i - 1]) << "step " << k + 1;
      }
    const double p = test::convergence_order(s.residuals, floor);
    if (std::isnan(p)) continue;
    ++checked;
    EXPECT_GE(p, 1.8) << "step " << k + 1 << ": " << table.str();
    record("newton_order_fabric_step_" + std::to_string(k + 1), p);
  }
  EXPECT_GE(checked, 1) << table.str();
  RecordProperty("newton_residuals_fabric", table.str());
  // Not homogeneous: the grip force differs from the law's force at the mean imposed strains.
  const double eC = 0.5 * (std::pow(1 + 40.0 / 55, 2) - 1), eW = 0.5 * (std::pow(1 + 3.0 / 55, 2) - 1);
  EXPECT_GT(std::abs(r.steps.back().force_per_width - law.forces(eC, eW)(0)), 1e-3 * law.forces(eC, eW)(0));
}

TEST(Simulate, BothSparseSolversGiveTheSameSolution) {
  // Eigen's SimplicialLDLT (default) and CHOLMOD's LDLᵀ: the converged states and sensitivities agree
  // to the Newton tolerance.
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  TestModel t = model(strip(ElementType::Q8, 3, 12, 10, 50), {});
  for (int k = 1; k <= 12; ++k) t.loads.push_back(50.0 * k / 12);
  std::vector<SimulationResult> runs;
  for (LinearSolverKind kind : {LinearSolverKind::eigen_ldlt, LinearSolverKind::cholmod_ldlt}) {
    SolveOptions o = tight();
    o.linear_solver = kind;
    o.sensitivities = true;
    runs.push_back(simulate(t, law, o));
    ASSERT_TRUE(runs.back().usable()) << runs.back().message;
  }
  constexpr double kSame = 1e-9;  // Newton tolerance 1e-13 of the reactions, conditioning ~1e3
  for (size_t k = 0; k < t.loads.size(); ++k) {
    const StepResult &a = runs[0].steps[k], &b = runs[1].steps[k];
    EXPECT_LT((a.u - b.u).cwiseAbs().maxCoeff(), kSame * a.u.cwiseAbs().maxCoeff()) << "step " << k;
    EXPECT_NEAR(a.edge_force, b.edge_force, kSame * std::abs(a.edge_force));
    EXPECT_LT((a.du_dc - b.du_dc).cwiseAbs().maxCoeff(), kSame * a.du_dc.cwiseAbs().maxCoeff());
  }
}

// ---------------------------------------------------------------------------------------------------

// du/dc and d(edge force)/dc at every step against central differences of whole simulations.
// `afterwards`: simulated without them, then fem::add_sensitivities from the converged states.
void check_sensitivities(TestModel t, const Law& law0, const std::string& tag, bool afterwards = false) {
  SolveOptions o = tight();
  o.sensitivities = !afterwards;
  SimulationResult r = simulate(t, law0, o);
  ASSERT_TRUE(r.usable()) << r.message;
  if (afterwards) {
    ASSERT_TRUE(r.steps.front().du_dc.size() == 0);
    ASSERT_TRUE(add_sensitivities(t, law0, r, o)) << r.message;
  }
  const Eigen::VectorXd c = law0.coefficients();
  o.sensitivities = false;
  double worst_u = 0, worst_f = 0;
  for (int k = 0; k < c.size(); ++k) {
    const double h = 1e-5 * std::abs(c(k));
    std::vector<SimulationResult> pm;
    for (double s : {1.0, -1.0}) {
      auto law = law0.clone();
      Eigen::VectorXd cc = c;
      cc(k) += s * h;
      law->set_coefficients(cc);
      pm.push_back(simulate(t, *law, o));
      ASSERT_TRUE(pm.back().usable());
    }
    for (size_t step = 0; step < r.steps.size(); ++step) {
      const Eigen::VectorXd du = (pm[0].steps[step].u - pm[1].steps[step].u) / (2 * h);
      const double df = (pm[0].steps[step].edge_force - pm[1].steps[step].edge_force) / (2 * h);
      const double eu = (r.steps[step].du_dc.col(k) - du).cwiseAbs().maxCoeff() / du.cwiseAbs().maxCoeff();
      worst_u = std::max(worst_u, eu);
      EXPECT_LT(eu, kFdSimulate) << tag << " coefficient " << k << " step " << step;
      if (t.control == GripControl::displacement) {
        const double ef = std::abs(r.steps[step].dforce_dc(k) - df) / std::abs(df);
        worst_f = std::max(worst_f, ef);
        EXPECT_LT(ef, kFdSimulate) << tag << " coefficient " << k << " step " << step;
      } else {
        EXPECT_EQ(r.steps[step].dforce_dc(k), 0);
      }
    }
  }
  record(std::string("sensitivity_du_fd_error_") + tag, worst_u);
  record(std::string("sensitivity_force_fd_error_") + tag, worst_f);
}

TEST(Sensitivities, MatchFiniteDifferencesUnderDisplacementControl) {
  TestModel t = model(strip(ElementType::Q8, 3, 5, 10, 25), {3, 6, 10});
  t.material_angle = 20;
  t.side = SideEdge::guide;
  t.guide = {-1.5};
  check_sensitivities(t, test::TestingLaw(1.0, 2.0, 0.5), "displacement");
  check_sensitivities(t, MooneyRivlin(paper_mooney_rivlin_terms()), "displacement_mooney");
  check_sensitivities(t, MooneyRivlin(paper_mooney_rivlin_terms()), "displacement_mooney_afterwards", true);
}

TEST(Sensitivities, MatchFiniteDifferencesUnderForceControl) {
  TestModel t = model(strip(ElementType::Q8, 3, 5, 10, 25), {2, 5, 8});
  t.control = GripControl::force;
  check_sensitivities(t, test::TestingLaw(1.0, 2.0, 0.5), "force");
  check_sensitivities(t, test::TestingLaw(1.0, 2.0, 0.5), "force_afterwards", true);
}

TEST(MeshConvergence, GripForceOfTheClampedStripConvergesFasterWithQ8) {
  // Clamped uniaxial strip to 50 % strain, meshes 2×5, 4×10, 8×20, 16×40 (3 refinements). The clamp's
  // corner singularity limits the rate; each refinement must still shrink the change ≥ 2.5× (measured
  // ~3.1 for Q4, ~3.5 for Q8), and Q8's change must be below Q4's at every level.
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  std::map<ElementType, std::vector<double>> force;
  for (ElementType type : {ElementType::Q4, ElementType::Q8})
    for (int r : {1, 2, 4, 8}) {
      const SimulationResult res = simulate(model(strip(type, 2 * r, 5 * r, 10, 25), {2.5, 5, 7.5, 10, 12.5}), law);
      ASSERT_TRUE(res.usable()) << res.message;
      force[type].push_back(res.steps.back().edge_force);
      record(std::string("grip_force_") + to_string(type) + "_" + std::to_string(2 * r) + "x" + std::to_string(5 * r),
             res.steps.back().edge_force, 9);
    }
  for (size_t k = 1; k + 1 < 4; ++k)
    for (ElementType type : {ElementType::Q4, ElementType::Q8}) {
      const auto& f = force[type];
      EXPECT_GT(std::abs(f[k] - f[k - 1]), 2.5 * std::abs(f[k + 1] - f[k])) << to_string(type) << " level " << k;
    }
  for (size_t k = 1; k < 4; ++k)
    EXPECT_LT(std::abs(force[ElementType::Q8][k] - force[ElementType::Q8][k - 1]),
              std::abs(force[ElementType::Q4][k] - force[ElementType::Q4][k - 1]));
  EXPECT_NEAR(force[ElementType::Q4][3], force[ElementType::Q8][3], 1e-3 * force[ElementType::Q8][3]);
}

// ---------------------------------------------------------------------------------------------------

TEST(LoadStepping, ALoadPastTheMaximumForceEndsNotConvergedWithoutThrowing) {
  // A saturating law has a maximum force (about 0.6 N per mm of width here); 50 N cannot be carried.
  const test::TestingLaw law(1.0, 2.0, 0.0, 0.5);
  TestModel t = model(strip(ElementType::Q4, 2, 3, 1, 3), {0.1, 50});
  t.control = GripControl::force;
  SolveOptions o;
  o.max_cutbacks = 4;
  SimulationResult r;
  ASSERT_NO_THROW(r = simulate(t, law, o));
  EXPECT_EQ(r.termination, SolveTermination::not_converged) << r.message;
  EXPECT_FALSE(r.usable());
  ASSERT_EQ(r.steps.size(), 1u);
  EXPECT_NE(r.message.find("step 2 of 2"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("4 cutbacks"), std::string::npos) << r.message;
}

TEST(LoadStepping, AForceControlledLawWithoutTensileEquilibriumIsInvalidNotCompressed) {
  // C10 < 0: the initial stiffness is negative, and Newton finds only compressed equilibria (grip
  // displacement < 0 under a tensile force). Such a state is not usable: invalid_state, no throw.
  TestModel t = model(strip(ElementType::Q8, 3, 6, 10, 25), {0.1, 0.2});
  t.control = GripControl::force;
  SimulationResult r;
  ASSERT_NO_THROW(r = simulate(t, MooneyRivlin({{1, 0, -0.1}})));
  EXPECT_EQ(r.termination, SolveTermination::invalid_state) << r.message;
  EXPECT_TRUE(r.steps.empty());
  EXPECT_NE(r.message.find("compressed"), std::string::npos) << r.message;
  // C10 = 0.01, C20 = −0.05: the force peaks near 0.1 N and falls after; past the peak no step may be
  // returned with the grip pulled inward.
  t.loads = {0.02, 0.04, 0.06, 0.08, 0.12, 0.2, 0.4};
  ASSERT_NO_THROW(r = simulate(t, MooneyRivlin({{1, 0, 0.01}, {2, 0, -0.05}})));
  EXPECT_FALSE(r.usable()) << r.message;
  EXPECT_LT(r.steps.size(), t.loads.size());
  for (const StepResult& s : r.steps) EXPECT_GT(s.edge_displacement, 0) << "load " << s.load;
}

TEST(LoadStepping, ALargeStepIsCutBackAndConverges) {
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  TestModel t = model(strip(ElementType::Q8, 2, 4, 10, 25), {40});  // one step to 160 % strain
  SolveOptions o;
  o.max_iterations = 6;
  const SimulationResult r = simulate(t, law, o);
  ASSERT_TRUE(r.usable()) << r.message;
  EXPECT_GT(r.steps[0].cutbacks, 0);
}

TEST(LoadStepping, AGuidePastTheOppositeEdgeIsAnInvalidState) {
  const test::TestingLaw law(1.0, 2.0);
  TestModel t = model(strip(ElementType::Q4, 2, 2, 10, 10), {1, 2});
  t.side = SideEdge::guide;
  t.guide = {-5, -15};  // the side edge would cross x = 0: elements must invert
  const SimulationResult r = simulate(t, law);
  EXPECT_EQ(r.termination, SolveTermination::invalid_state) << r.message;
  EXPECT_EQ(r.steps.size(), 1u);
  EXPECT_NE(r.message.find("inverted"), std::string::npos) << r.message;
}

TEST(SolveOptions, BadValuesThrowNamingTheKey) {
  auto key_of = [](SolveOptions o) -> std::string {
    try {
      o.validate();
    } catch (const InputError& e) {
      return e.where().key;
    }
    return "";
  };
  SolveOptions o;
  EXPECT_EQ(key_of(o), "");
  o = {}, o.tolerance = 0;
  EXPECT_EQ(key_of(o), "solver.tolerance");
  o = {}, o.max_iterations = 0;
  EXPECT_EQ(key_of(o), "solver.max_iterations");
  o = {}, o.max_cutbacks = 31;
  EXPECT_EQ(key_of(o), "solver.max_cutbacks");
}

TEST(Simulate, ReportsOneProgressPerStepAndTimings) {
  const test::TestingLaw law;
  const TestModel t = model(strip(ElementType::Q4, 2, 2), {1, 2, 3});
  std::vector<Progress> seen;
  Reporter rep;
  rep.progress = [&](const Progress& p) { seen.push_back(p); };
  const SimulationResult r = simulate(t, law, {}, rep);
  ASSERT_TRUE(r.usable());
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen.back().done, 3u);
  EXPECT_EQ(seen.back().total, 3u);
  EXPECT_GT(r.factorizations, 0);
  EXPECT_GE(r.seconds, r.factorization_seconds);
  EXPECT_STREQ(to_string(r.termination), "converged");
}

TEST(Simulate, ABriefReportSaysTheStepsTheNewtonWorkAndTheFinalForce) {
  const test::TestingLaw law;
  const TestModel t = model(strip(ElementType::Q4, 2, 2), {1, 2, 3});
  SimulationResult r = simulate(t, law);
  ASSERT_TRUE(r.usable());
  int iterations = 0;
  for (const StepResult& s : r.steps) iterations += s.iterations;
  r.seconds = 0.781;
  char force[160];
  std::snprintf(force, sizeof force, "; final force %.5g N (%.5g N/mm) at %.5g mm", r.steps.back().edge_force,
                r.steps.back().force_per_width, r.steps.back().edge_displacement);
  EXPECT_EQ(r.brief_report(),
            "3 steps, " + std::to_string(iterations) + " Newton iterations, 0 cutbacks, 781 ms" + force);
  r.steps.clear();
  EXPECT_EQ(r.brief_report(), "no step converged, 781 ms");
}

TEST(Simulate, InvalidModelThrowsBeforeAnyWork) {
  const test::TestingLaw law;
  // Loads that go back under force control (displacement control takes any path: issue 29).
  TestModel t = model(strip(ElementType::Q4, 2, 2), {1, 0.5});
  t.control = GripControl::force;
  EXPECT_THROW(simulate(t, law), InputError);
}

}  // namespace
}  // namespace tricot::fem
