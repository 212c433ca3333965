#include "tricot/fem/wrinkling.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "testing/fd_check.hpp"
#include "testing/law_eval.hpp"
#include "testing/newton.hpp"
#include "testing/record.hpp"
#include "testing/states.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/corotational.hpp"
#include "tricot/fem/mesh.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/neo_hookean.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/response_surface.hpp"
#include "tricot/fem/solver.hpp"

using namespace tricot;
using namespace tricot::fem;
using tricot::test::JacobianMatches;
using tricot::test::P_of;
using tricot::test::rot;

namespace {

/// Central differences (h = 1e-6) of a smooth map are exact to ~1e-9 relative; the implicit
/// derivatives of the wrinkle solve add the solve's tolerance (1e-13 relative). A missing term is O(1).
constexpr double kFdTol = 1e-7;
/// Central-difference step of the coefficients near the slack switch: there P (~1e-4 N/mm) carries
/// the round-off of the larger η P(F) (~1e-17), which h = 1e-6 turns into 1e-11 noise on 1e-4.
/// Elsewhere h = 1e-6 (the smoothed switch's curvature 1/(2w) makes 1e-5 truncate at 2e-7).
constexpr double kCoefficientStepNearSlack = 1e-5;
/// Closed forms that the wrinkle solve meets to its tolerance (1e-13 of |P| |F|), with room.
constexpr double kSolve = 1e-10;

struct NamedLaw {
  std::string name;
  std::shared_ptr<Law> law;
  Mat2 Q;
};

/// The paper14 start of the 110 mm campaign (examples/knit-campaign/project-110.toml).
ResponseSurface campaign_paper14() {
  ResponseSurface rs = ResponseSurface::preset("paper14", 0.05);
  Eigen::VectorXd c(14);
  c << 0.39279, -0.000371527, 4.64332e-05, 0.000466978, 0.00083818, 0.00115181, 0.00620026, 0.0147041, 0.226856,
      -0.0025306, -0.00514861, 0, 0.00627933, 0.0119436;
  rs.set_coefficients(c);
  return rs;
}

std::vector<NamedLaw> laws() {
  return {{"neo-Hookean", std::make_shared<NeoHookean>(0.1, 0.2), Mat2::Identity()},
          {"Mooney-Rivlin", std::make_shared<MooneyRivlin>(paper_mooney_rivlin_terms()), Mat2::Identity()},
          {"corotational orthotropic 30 deg", std::make_shared<CorotationalOrthotropic>(1.0, 0.5, 0.1, 0.05), rot(30)},
          {"response surface paper14 -20 deg", std::make_shared<ResponseSurface>(campaign_paper14()), rot(-20)},
          {"reference fabric 75 deg", std::make_shared<ReferenceFabric>(), rot(75)}};
}

/// F = R(φ) diag(λ1, λ2) R(ψ) with the given stretches.
Mat2 stretch(double l1, double l2, double phi = 25, double psi = -10) {
  return rot(phi) * Mat2(Vec2(l1, l2).asDiagonal()) * rot(psi);
}

/// λ2 in (lo, hi) where `pred(λ2)` switches from false (at lo) to true (at hi), by bisection.
double bisect(const std::function<bool(double)>& pred, double lo, double hi) {
  for (int i = 0; i < 200 && hi - lo > 1e-14; ++i) {
    const double m = 0.5 * (lo + hi);
    (pred(m) ? hi : lo) = m;
  }
  return 0.5 * (lo + hi);
}

/// The states to check one law at: taut, wrinkled, slack, and on each side of the taut/wrinkled
/// (1e-4 relative) and wrinkled/slack (1e-3) switches along F = stretch(λ1, λ2).
std::vector<test::State> states(const WrinklingLaw& law, const Mat2& Q) {
  auto state_at = [&](double l1, double l2) { return law.state({stretch(l1, l2), Q}).state; };
  const double l1 = 1.25;
  // Along λ2 from 0.55 (well compressed across: wrinkled) to 1.25 (equibiaxial: taut).
  const double taut_switch = bisect([&](double l2) { return state_at(l1, l2) == MembraneState::taut; }, 0.55, 1.25);
  std::vector<test::State> s = {
      {"taut", stretch(1.3, 1.15)},
      {"wrinkled", stretch(1.3, 0.7)},
      {"slack", stretch(0.8, 0.85)},
      {"taut near the switch", stretch(l1, taut_switch * (1 + 1e-4))},
      {"wrinkled near the taut switch", stretch(l1, taut_switch * (1 - 1e-4))},
  };
  // Within the smoothed switch: past the sharp switch (root β = 0) by 3e-4 toward taut, root β < 0.
  const double sharp = bisect(
      [&](double l2) {
        const WrinkleState w = law.state({stretch(l1, l2), Q});
        return w.state == MembraneState::taut || w.root_beta < 0;
      },
      0.55, 1.25);
  s.push_back({"wrinkled within the smoothed switch", stretch(l1, sharp * (1 + 3e-4))});
  // Along λ1 from 0.8 (slack) to 1.25 (wrinkled) at λ2 = 0.7.
  const double slack_switch = bisect([&](double a) { return state_at(a, 0.7) == MembraneState::wrinkled; }, 0.8, 1.25);
  // 1e-3 here: the wrinkle angle is singular at the slack switch (the tension that fixes it vanishes),
  // its derivatives grow like 1/tension, and central differences need the room.
  s.push_back({"wrinkled near the slack switch", stretch(slack_switch * (1 + 1e-3), 0.7)});
  s.push_back({"slack near the switch", stretch(slack_switch * (1 - 1e-3), 0.7)});
  return s;
}

MembraneState expected_state(const std::string& name) {
  if (name.rfind("taut", 0) == 0) return MembraneState::taut;
  if (name.rfind("wrinkled", 0) == 0) return MembraneState::wrinkled;
  return MembraneState::slack;
}

}  // namespace

TEST(WrinklingLaw, APullAndASqueezeAcrossWrinkleWithZeroTransverseStress) {
  // F = diag(1.3, 0.8) on a neo-Hookean sheet: free, a uniaxial pull to 1.3 narrows it to λ2* (P22 = 0)
  // with λ2* > 0.8, so the sheet is squeezed across: wrinkled along x, β = λ2*/0.8 − 1, and P is the
  // uniaxial force at diag(1.3, λ2*), found here by bisection on the inner law alone.
  const NeoHookean inner(0.1, 0.2);
  WrinklingOptions o;
  o.residual_stiffness = 0;  // the pure tension field
  const WrinklingLaw law(inner, o);
  const double l1 = 1.3, l2 = 0.8;
  const double l2_free =
      bisect([&](double b) { return P_of(inner, Vec2(l1, b).asDiagonal(), Mat2::Identity())(1, 1) > 0; }, 0.3, 1.3);
  ASSERT_GT(l2_free, l2);
  const Mat2 F = Vec2(l1, l2).asDiagonal();
  const WrinkleState st = law.state({F, Mat2::Identity()});
  ASSERT_EQ(st.state, MembraneState::wrinkled);
  EXPECT_NEAR(st.angle, 0.0, kSolve);
  EXPECT_NEAR(st.beta, l2_free / l2 - 1, 1e-9);
  const Mat2 P = P_of(law, F, Mat2::Identity());
  const Mat2 P_uniaxial = P_of(inner, Vec2(l1, l2_free).asDiagonal(), Mat2::Identity());
  EXPECT_NEAR(P(1, 1), 0.0, kSolve * P_uniaxial(0, 0));
  EXPECT_NEAR(P(0, 1), 0.0, kSolve * P_uniaxial(0, 0));
  EXPECT_NEAR(P(1, 0), 0.0, kSolve * P_uniaxial(0, 0));
  EXPECT_NEAR(P(0, 0), P_uniaxial(0, 0), 1e-8 * P_uniaxial(0, 0));
  EXPECT_GT(P(0, 0), 0);
  // The inner law alone compresses across (the stress the wrinkles relieve).
  EXPECT_LT(P_of(inner, F, Mat2::Identity())(1, 1), 0);
  test::record("uniaxial_beta", st.beta, 6);
}

TEST(WrinklingLaw, ASheetSqueezedToAFewPercentAcrossStillCarriesTheUniaxialForce) {
  // A wrinkled sheet's force does not depend on how far it is squeezed across: F = diag(1.3, λ2) for
  // every λ2 below the free width λ2* carries the uniaxial force at diag(1.3, λ2*), with wrinkle
  // strain β = λ2*/λ2 − 1. At λ2 = 0.03 that is β ≈ 29: a cap on β (there was one at 10) turned such
  // a point slack, a jump of the whole force that stalled the FE's Newton at a slack corner of the rig.
  const NeoHookean inner(0.1, 0.2);
  WrinklingOptions o;
  o.residual_stiffness = 0;
  const WrinklingLaw law(inner, o);
  const double l1 = 1.3;
  const double l2_free =
      bisect([&](double b) { return P_of(inner, Vec2(l1, b).asDiagonal(), Mat2::Identity())(1, 1) > 0; }, 0.3, 1.3);
  const double force = P_of(inner, Vec2(l1, l2_free).asDiagonal(), Mat2::Identity())(0, 0);
  for (const double l2 : {0.5, 0.09, 0.0909, 0.03, 0.01}) {
    const Mat2 F = Vec2(l1, l2).asDiagonal();
    const WrinkleState st = law.state({F, Mat2::Identity()});
    ASSERT_EQ(st.state, MembraneState::wrinkled) << "λ2 = " << l2;
    EXPECT_NEAR(st.beta, l2_free / l2 - 1, 1e-8 * (l2_free / l2)) << "λ2 = " << l2;
    EXPECT_NEAR(P_of(law, F, Mat2::Identity())(0, 0), force, 1e-8 * force) << "λ2 = " << l2;
  }
}

TEST(WrinklingLaw, AnElementSqueezedToNothingAtAnAngleFindsItsWrinklesToRoundOff) {
  // A wrinkled point F0 with its root: reference direction m across the wrinkles, current n (Fᵀn = ℓ0 m)
  // and the wavy sheet's stretch s. Squeezing it further across, F(ℓ) = F0 + (ℓ − ℓ0) n mᵀ, keeps
  // Fᵀn = ℓ m, so the same wavy sheet F̃ = F + (s − ℓ) n mᵀ is the root for every ℓ < s: the same
  // (s, m) and the same force. At ℓ = 1e-7 (an element squeezed flat, det F ~ 1e-7) and a generic
  // angle, F̃ depends on n's angle through β |Fᵀt| ~ 1e7 times it, and a solve in (β, θ) cannot resolve
  // the root in a double (it stalled the rig's 24 × 20 wrinkling campaign at a clip corner). Solved in
  // (s, φ), φ the reference direction's angle, it is found to round-off (the (β, θ) solve was off by
  // 5e-9 of the force at ℓ = 1e-7 and went slack, losing it all, at 1e-8); an orthotropic law at rotated
  // material axes, sheared as well as squeezed.
  WrinklingOptions o;
  o.residual_stiffness = 0;  // the relaxed force alone (η P(F) changes with ℓ)
  const WrinklingLaw law(campaign_paper14(), o);
  const Mat2 Q = rot(0.4);
  const double alpha = 0.65, phi = -0.37, l1 = 1.3, tau = 0.2, ell0 = 0.3;
  const Vec2 n0(std::cos(alpha), std::sin(alpha)), t0(-n0(1), n0(0));
  const Vec2 m0(std::cos(phi), std::sin(phi)), mp0(-m0(1), m0(0));
  const Mat2 F0 = l1 * t0 * mp0.transpose() + (tau * t0 + ell0 * n0) * m0.transpose();
  const WrinkleState ref = law.state({F0, Q});
  ASSERT_EQ(ref.state, MembraneState::wrinkled);
  const Vec2 m(std::cos(ref.reference_angle), std::sin(ref.reference_angle));
  Vec2 n(std::sin(ref.angle), -std::cos(ref.angle));  // ⊥ the wrinkles, signed so that Fᵀn = ℓ m, ℓ > 0
  if (n.dot(F0 * m) < 0) n = -n;
  const double ell_ref = n.dot(F0 * m);
  const Mat2 P_ref = P_of(law, F0, Q);
  for (const double ell : {1e-2, 1e-4, 1e-7, 1e-9}) {
    const Mat2 F = F0 + (ell - ell_ref) * n * m.transpose();
    const WrinkleState st = law.state({F, Q});
    ASSERT_EQ(st.state, MembraneState::wrinkled) << "ℓ = " << ell;
    EXPECT_NEAR(st.stretch, ref.stretch, 1e-9 * ref.stretch) << "ℓ = " << ell;
    // β = s/ℓ − 1 carries the round-off of F's entries relative to ℓ (~1e-16/ℓ); s and P do not.
    EXPECT_NEAR(st.beta, ref.stretch / ell - 1, (1e-9 + 1e-15 / ell) * (ref.stretch / ell)) << "ℓ = " << ell;
    EXPECT_LT((P_of(law, F, Q) - P_ref).norm(), 1e-9 * P_ref.norm()) << "ℓ = " << ell;
  }
}

// The wrinkled zone of a mesh (VTU, identification outputs): a homogeneous field is wholly in one state.
TEST(ElementWrinkles, AHomogeneousFieldIsWhollyWrinkledOrSlackWithItsDirection) {
  MeshOptions mo;
  mo.width = 10, mo.height = 20, mo.nx = 2, mo.ny = 3;
  const Mesh mesh = make_quarter_mesh(mo);
  auto field = [&](const Mat2& F) {
    Eigen::VectorXd u(2 * mesh.nodes());
    for (int n = 0; n < mesh.nodes(); ++n) u.segment<2>(2 * n) = (F - Mat2::Identity()) * mesh.X.col(n);
    return u;
  };
  const WrinklingLaw law{NeoHookean(0.1, 0.2)};
  // Pulled 1.3 along y, squeezed 0.8 across: wrinkles along y (the tension direction t, angle 90°).
  const auto pulled = element_wrinkles(mesh, law, 0, field(Vec2(0.8, 1.3).asDiagonal()));
  ASSERT_EQ(pulled.size(), std::size_t(mesh.elements()));
  for (const ElementWrinkles& w : pulled) {
    EXPECT_NEAR(w.wrinkled, 1.0, 1e-12);
    EXPECT_EQ(w.slack, 0.0);
    EXPECT_NEAR(std::abs(w.angle), std::numbers::pi / 2, kSolve);
  }
  EXPECT_NEAR(wrinkled_and_slack_area(mesh, pulled)(0), 1.0, 1e-12);
  // Squeezed both ways: slack.
  const Vec2 slack = wrinkled_and_slack_area(mesh, element_wrinkles(mesh, law, 0, field(Vec2(0.8, 0.85).asDiagonal())));
  EXPECT_NEAR(slack(1), 1.0, 1e-12);
  EXPECT_EQ(slack(0), 0.0);
  // Stretched both ways: taut; and a law that does not wrinkle has no wrinkles.
  EXPECT_EQ(wrinkled_and_slack_area(mesh, element_wrinkles(mesh, law, 0, field(Vec2(1.2, 1.3).asDiagonal()))).norm(),
            0.0);
  EXPECT_EQ(
      wrinkled_and_slack_area(mesh, element_wrinkles(mesh, NeoHookean(0.1, 0.2), 0, field(Vec2(0.8, 1.3).asDiagonal())))
          .norm(),
      0.0);
}

TEST(WrinklingLaw, PureShearOfAnIsotropicLawGivesATensionFieldAt45Degrees) {
  // F = [[1, γ], [γ, 1]]: stretch 1 + γ along 45°, 1 − γ along −45°. An isotropic sheet wrinkles with
  // its tension along 45° (by symmetry) and none across.
  for (const double g : {0.05, 0.2}) {
    Mat2 F;
    F << 1, g, g, 1;
    for (const auto& [name, law_ptr] : std::vector<std::pair<std::string, std::shared_ptr<Law>>>{
             {"neo-Hookean", std::make_shared<NeoHookean>(0.1, 0.2)},
             {"corotational isotropic",
              std::make_shared<CorotationalOrthotropic>(CorotationalOrthotropic::isotropic(1, 2))},
             {"Mooney-Rivlin", std::make_shared<MooneyRivlin>(paper_mooney_rivlin_terms())}}) {
      WrinklingOptions o;
      o.residual_stiffness = 0;
      const WrinklingLaw law(*law_ptr, o);
      const WrinkleState st = law.state({F, Mat2::Identity()});
      ASSERT_EQ(st.state, MembraneState::wrinkled) << name << " γ = " << g;
      EXPECT_NEAR(st.angle, std::numbers::pi / 4, kSolve) << name << " γ = " << g;
      // σ n = 0 across the wrinkles (n along −45°): P Fᵀ n = 0.
      const Mat2 P = P_of(law, F, Mat2::Identity());
      const Vec2 n(std::sqrt(0.5), -std::sqrt(0.5));
      EXPECT_LE((P * F.transpose() * n).norm(), kSolve * P.norm()) << name;
      EXPECT_GT(st.tension, 0);
    }
  }
}

TEST(WrinklingLaw, StatesAreTautWrinkledAndSlackAsExpected) {
  for (const auto& L : laws()) {
    const WrinklingLaw law(*L.law);
    for (const auto& s : states(law, L.Q)) {
      EXPECT_EQ(law.state({s.F, L.Q}).state, expected_state(s.name)) << L.name << ": " << s.name;
    }
    // At rest: taut (the FE leaves the unstressed state with the law's own tangent).
    EXPECT_EQ(law.state({Mat2::Identity(), L.Q}).state, MembraneState::taut) << L.name;
  }
}

TEST(WrinklingLaw, TangentMatchesFiniteDifferencesInEveryStateAndNearTheSwitches) {
  double worst = 0;
  for (const auto& L : laws()) {
    const WrinklingLaw law(*L.law);
    for (const auto& s : states(law, L.Q)) {
      LawOutput out;
      law.evaluate({s.F, L.Q}, {true, false}, out);
      auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return flatten(P_of(law, unflatten(Vec4(x)), L.Q)); };
      EXPECT_TRUE(JacobianMatches(P, flatten(s.F), out.A, kFdTol)) << L.name << ": " << s.name;
      worst = std::max(worst, test::jacobian_error(P, flatten(s.F), out.A));
    }
  }
  test::record_scientific("max_tangent_fd_rel_error", worst);
}

TEST(WrinklingLaw, CoefficientSensitivitiesMatchFiniteDifferencesInEveryState) {
  double worst = 0;
  for (const auto& L : laws()) {
    const WrinklingLaw law(*L.law);
    const Eigen::VectorXd c0 = law.coefficients();
    for (const auto& s : states(law, L.Q)) {
      LawOutput out;
      law.evaluate({s.F, L.Q}, {false, true}, out);
      ASSERT_EQ(out.dP_dc.size(), static_cast<std::size_t>(c0.size()));
      Eigen::MatrixXd J(4, c0.size());
      for (Eigen::Index k = 0; k < c0.size(); ++k) J.col(k) = flatten(out.dP_dc[static_cast<std::size_t>(k)]);
      auto P = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
        WrinklingLaw l = law;
        l.set_coefficients(c);
        return flatten(P_of(l, s.F, L.Q));
      };
      const double h = s.name.find("slack switch") != std::string::npos ? kCoefficientStepNearSlack : 1e-6;
      EXPECT_TRUE(JacobianMatches(P, c0, J, kFdTol, h)) << L.name << ": " << s.name;
      worst = std::max(worst, test::jacobian_error(P, c0, J, h));
    }
  }
  test::record_scientific("max_dP_dc_fd_rel_error", worst);
}

TEST(WrinklingLaw, TautIsTheInnerLawAndSlackKeepsTheResidualFraction) {
  const ReferenceFabric inner;
  const WrinklingLaw law(inner);
  const double eta = law.options().residual_stiffness;
  const Mat2 Q = rot(75);
  const Mat2 taut = stretch(1.3, 1.15), slack = stretch(0.8, 0.85);
  LawOutput wt, it, ws, is;
  law.evaluate({taut, Q}, {true, true}, wt);
  inner.evaluate({taut, Q}, {true, true}, it);
  EXPECT_EQ(wt.P, it.P);
  EXPECT_EQ(wt.A, it.A);
  law.evaluate({slack, Q}, {true, true}, ws);
  inner.evaluate({slack, Q}, {true, true}, is);
  EXPECT_LE((ws.P - eta * is.P).norm(), 1e-15 * is.P.norm());
  EXPECT_LE((ws.A - eta * is.A).norm(), 1e-15 * is.A.norm());
  EXPECT_FALSE(law.linear_in_coefficients());
  EXPECT_EQ(law.name(), inner.name());
}

TEST(WrinklingLaw, BadOptionsThrowNamingTheKey) {
  const NeoHookean inner(0.1, 0.2);
  WrinklingOptions o;
  o.residual_stiffness = 0.7;
  try {
    WrinklingLaw law(inner, o);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "law.residual_stiffness");
  }
}

TEST(WrinklingLaw, NewtonConvergesQuadraticallyOnAStripPulledAndNarrowed) {
  // A neo-Hookean quarter specimen 10 × 25 mm, 4 × 8 Q8, clamped grip pulled 5 mm (20 %) in 5 steps,
  // side edge narrowed with it by a guide to −1 mm (−2 mm inverts the corner element, where the
  // clamp holds u_x = 0 against the guide, with or without wrinkles): the guide squeezes the sheet across while the
  // grip pulls it, so most of it wrinkles (the clamp keeps the corner taut). No cutback: each step's history is one
  // Newton run.
  const WrinklingLaw law(NeoHookean(0.1, 0.2));
  MeshOptions m;
  m.type = ElementType::Q8, m.nx = 4, m.ny = 8, m.width = 10, m.height = 25;
  TestModel t;
  t.name = "t";
  t.mesh = make_quarter_mesh(m);
  t.loads = {1, 2, 3, 4, 5};
  t.side = SideEdge::guide;
  t.guide = {-1};
  SolveOptions o;
  o.tolerance = 1e-13;
  o.max_cutbacks = 0;
  const SimulationResult r = simulate(t, law, o);
  ASSERT_TRUE(r.usable()) << r.message;
  const StepResult& step = r.steps.back();
  // The centre element is wrinkled: evaluate the law at its deformation (centre of the quarter).
  int wrinkled = 0, points = 0;
  for (int e = 0; e < t.mesh.elements(); ++e) {
    // Mean F of the element from its corner nodes' displacements (bilinear estimate at the centre).
    const auto& nodes = t.mesh.connectivity[static_cast<std::size_t>(e)];
    Vec2 X0 = t.mesh.X.col(nodes[0]), X2 = t.mesh.X.col(nodes[2]);
    const Vec2 u0 = step.u.segment<2>(2 * nodes[0]), u1 = step.u.segment<2>(2 * nodes[1]);
    const Vec2 u2 = step.u.segment<2>(2 * nodes[2]), u3 = step.u.segment<2>(2 * nodes[3]);
    const double hx = X2(0) - X0(0), hy = X2(1) - X0(1);
    Mat2 F = Mat2::Identity();
    F.col(0) += 0.5 * ((u1 - u0) + (u2 - u3)) / hx;
    F.col(1) += 0.5 * ((u3 - u0) + (u2 - u1)) / hy;
    ++points;
    if (law.state({F, Mat2::Identity()}).state == MembraneState::wrinkled) ++wrinkled;
  }
  EXPECT_GE(wrinkled, points / 2) << wrinkled << " of " << points;
  // Every step's order from its last three residuals above round-off (1e-10 of its first): the
  // states switch in the first iterations, then Newton on the relaxed law is quadratic.
  std::ostringstream hist;
  int checked = 0;
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const std::vector<double>& res = r.steps[k].residuals;
    EXPECT_EQ(r.steps[k].cutbacks, 0);
    hist << "step " << k + 1 << ":";
    for (double x : res) hist << " " << x;
    hist << "; ";
    const double p = test::convergence_order(res, 1e-10 * res[0]);
    if (std::isnan(p)) continue;
    ++checked;
    EXPECT_GE(p, 1.8) << "step " << k + 1 << ": " << hist.str();
    test::record("newton_order_wrinkled_step_" + std::to_string(k + 1), p);
  }
  EXPECT_GE(checked, 3) << hist.str();
  RecordProperty("newton_residuals_wrinkled", hist.str());
  test::record("wrinkled_elements", wrinkled);
}
