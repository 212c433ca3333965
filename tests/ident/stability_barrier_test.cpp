#include "tricot/ident/stability_barrier.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "testing/fd_check.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/response_surface.hpp"
#include "tricot/ident/identify.hpp"
#include "tricot/ident/synthetic.hpp"
#include "uniaxial.hpp"

namespace tricot::ident {
namespace {

// The barrier's A_i come from central differences (h = 1e-7) of polynomials with O(1) coefficients:
// truncation ~h², round-off ~1e-16/h ≈ 1e-9.
constexpr double kBasis = 1e-7;
// Central differences of the barrier (piecewise linear/quadratic in J, every row away from its kink).
constexpr double kFd = 1e-6;

/// paper14 with a1 = 0.25, b1 = d1 = coupling, c1 = 0.06 (the others 0): in tension A is constant,
/// [[0.25, coupling], [coupling, 0.06]], det A = 0.015 − coupling².
fem::ResponseSurface law(double coupling) {
  fem::ResponseSurface rs = fem::ResponseSurface::preset("paper14", 0.05);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(14);
  c(0) = 0.25, c(6) = coupling, c(8) = 0.06, c(12) = coupling;
  rs.set_coefficients(c);
  return rs;
}

struct Fixture {
  fem::TestModel model = test::uniaxial(1, 2, 2, fem::GripControl::displacement);
  std::unique_ptr<Objective> objective;
  explicit Fixture(double coupling) {
    const fem::ResponseSurface rs = law(coupling);
    const fem::SimulationResult sim = fem::simulate(model, rs);
    EXPECT_TRUE(sim.usable()) << sim.message;
    Experiment e;
    e.tests.push_back(measure(model, sim, test::field_points(2, 2), {}, FieldKind::cumulative));
    std::vector<Parameter> p{{"a1", 0.25}, {"b1", coupling}, {"c1", 0.06}, {"d1", coupling}};
    objective = std::make_unique<Objective>(std::vector<fem::TestModel>{model}, e, rs, p);
  }
};

StabilityBarrierOptions small_grid() {
  StabilityBarrierOptions o;
  o.eC_min = 0.05, o.eC_max = 0.25, o.eW_min = 0.05, o.eW_max = 0.25, o.step = 0.1;  // 3 × 3, all in tension
  return o;
}

TEST(StabilityBarrier, IsZeroForAStableLawAndGrowsAsTheDeterminantFallsBelowItsMargin) {
  Fixture f(0.1);
  const StabilizedObjective s(*f.objective, small_grid());
  ASSERT_EQ(s.grid().size(), 9u);
  Eigen::VectorXd J(4);
  J << 0.25, 0.1, 0.06, 0.1;  // det A = 0.015 − 0.01 = 0.005 > 2e-3
  for (const Mat2& A : s.force_jacobians(J)) EXPECT_NEAR(A.determinant(), 0.005, kBasis);
  EXPECT_EQ(s.barrier(J).norm(), 0.0);
  J << 0.25, 0.2, 0.06, 0.1;  // det A = 0.015 − 0.02 = −0.005: r = (2e-3 + 5e-3) / 2e-3 = 3.5
  const Eigen::VectorXd r = s.barrier(J);
  for (int g = 0; g < 9; ++g) {
    EXPECT_EQ(r(3 * g), 0.0);
    EXPECT_EQ(r(3 * g + 1), 0.0);
    EXPECT_NEAR(r(3 * g + 2), 3.5, 1e-5);
  }
  J << 0.25, 0.1, 0.005, 0.01;  // own wale slope 0.005 < 1e-2: r = (1e-2 − 5e-3) / 1e-2 = 0.5
  EXPECT_NEAR(s.barrier(J)(1), 0.5, 1e-5);
}

TEST(StabilityBarrier, JacobianMatchesFiniteDifferences) {
  Fixture f(0.1);
  StabilityBarrierOptions o;  // the default grid, compression included
  o.acoustic_margin = 0;      // the strain-space rows (the ellipticity rows: the next test)
  const StabilizedObjective s(*f.objective, o);
  Eigen::VectorXd J(4);
  J << 0.2, 0.18, 0.03, 0.15;  // unstable over much of the grid
  Eigen::MatrixXd Jb;
  const Eigen::VectorXd r = s.barrier(J, &Jb);
  ASSERT_GT(r.norm(), 0.0);
  auto barrier = [&](const Eigen::VectorXd& x) { return s.barrier(x); };
  EXPECT_TRUE(tricot::test::JacobianMatches(barrier, J, Jb, kFd, 1e-7));
}

TEST(StabilityBarrier, EllipticityRowsJacobianMatchesFiniteDifferences) {
  Fixture f(0.1);
  const StabilizedObjective s(*f.objective, StabilityBarrierOptions{});  // the default grid and margins
  const Eigen::Index first = 3 * static_cast<Eigen::Index>(s.grid().size());
  ASSERT_EQ(s.barrier_rows(), first + static_cast<Eigen::Index>(s.grid().size()));
  Eigen::VectorXd J(4);
  J << 0.2, 0.18, 0.0301, 0.15;  // a strong coupling: taut points lose ellipticity; no point at zero force
  Eigen::MatrixXd Jb;
  const Eigen::VectorXd r = s.barrier(J, &Jb);
  ASSERT_GT(r.tail(s.grid().size()).norm(), 0.0);
  auto rows = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return s.barrier(x).tail(s.grid().size()); };
  EXPECT_TRUE(tricot::test::JacobianMatches(rows, J, Jb.bottomRows(s.grid().size()), kFd, 1e-7));
}

TEST(StabilityBarrier, AppendsItsRowsToTheObjectivesEvaluation) {
  Fixture f(0.1);
  const StabilizedObjective s(*f.objective, small_grid());
  EXPECT_EQ(s.residuals(), f.objective->residuals() + 36);  // 9 points × (3 + 1 ellipticity row)
  Eigen::VectorXd J(4);
  J << 0.26, 0.2, 0.06, 0.1;
  const Evaluation a = f.objective->evaluate(J, true), b = s.evaluate(J, true);
  ASSERT_TRUE(a.ok && b.ok) << a.message << b.message;
  ASSERT_EQ(b.r.size(), s.residuals());
  EXPECT_EQ((b.r.head(a.r.size()) - a.r).norm(), 0.0);
  EXPECT_EQ((b.r.tail(36) - s.barrier(J)).norm(), 0.0);
  ASSERT_EQ(b.jacobian.rows(), s.residuals());
  EXPECT_EQ((b.jacobian.topRows(a.r.size()) - a.jacobian).norm(), 0.0);
  // Problem::lower_bound: the barrier's part of f, which needs no FE; the rest of f is ≥ 0.
  EXPECT_EQ(s.lower_bound(J), 0.5 * s.barrier(J).squaredNorm());
  EXPECT_NEAR(b.objective(), a.objective() + s.lower_bound(J), 1e-14 * b.objective());
}

// The margins leave the campaign's truth unpenalised: the reference knit (docs/theory/fabric.md §4)
// is stable with them over the whole default grid.
TEST(StabilityBarrier, DefaultMarginsLeaveTheReferenceKnitUnpenalised) {
  const fem::ReferenceFabric knit([] {
    fem::ReferenceFabricParameters p;
    p.G_s = 0.05;
    return p;
  }());
  const StabilityBarrierOptions o;
  constexpr double h = 1e-6;
  double det_min = 1e300, slope_min = 1e300, acoustic_min = 1e300;
  for (double eC = o.eC_min; eC <= o.eC_max + 1e-9; eC += o.step)
    for (double eW = o.eW_min; eW <= o.eW_max + 1e-9; eW += o.step) {
      Mat2 A;
      A.col(0) = (knit.forces(eC + h, eW) - knit.forces(eC - h, eW)) / (2 * h);
      A.col(1) = (knit.forces(eC, eW + h) - knit.forces(eC, eW - h)) / (2 * h);
      det_min = std::min(det_min, A.determinant());
      slope_min = std::min({slope_min, A(0, 0), A(1, 1)});
      // Strong ellipticity where taut (both principal values of P Fᵀ above σ₀, the gate's full weight).
      const Mat2 F = Vec2(std::sqrt(1 + 2 * eC), std::sqrt(1 + 2 * eW)).asDiagonal();
      fem::LawOutput out;
      knit.evaluate({F, Mat2::Identity()}, {true, false}, out);
      const Mat2 S = out.P * F.transpose();
      if (Eigen::SelfAdjointEigenSolver<Mat2>(0.5 * (S + S.transpose())).eigenvalues()(0) > 0)
        acoustic_min = std::min(acoustic_min, fem::strong_ellipticity(out.A).min_eigenvalue);
    }
  EXPECT_GT(det_min, o.det_margin);
  EXPECT_GT(slope_min, o.slope_margin);
  EXPECT_GT(acoustic_min, o.acoustic_margin);
  ::testing::Test::RecordProperty("reference_acoustic_min", std::to_string(acoustic_min));
  ::testing::Test::RecordProperty("reference_det_min", std::to_string(det_min));
  ::testing::Test::RecordProperty("reference_slope_min", std::to_string(slope_min));
}

// LM on the stabilized objective from a start past the instability (coupling 0.14: det A < 2e-3)
// returns to the truth (coupling 0.1, det A = 5e-3, the barrier inactive there).
TEST(StabilityBarrier, LmOnTheStabilizedObjectiveRecoversAStableTruth) {
  Fixture f(0.1);
  std::vector<Parameter> p{{"a1", 0.25}, {"b1", 0.14}, {"c1", 0.06}, {"d1", 0.14}};
  const Objective o(f.objective->models(), f.objective->experiment(), law(0.1), p);
  const StabilizedObjective s(o);
  IdentifyOptions options;
  options.stability_test = false;
  const IdentifyResult r = identify(s, options);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_NEAR(r.parameters(1), 0.1, 1e-4);
  EXPECT_NEAR(r.parameters(3), 0.1, 1e-4);
  EXPECT_EQ(r.uncertainty.std_error.size(), 4);
}

TEST(StabilityBarrier, BadOptionsAreAnInputErrorNamingTheField) {
  Fixture f(0.1);
  StabilityBarrierOptions o;
  o.step = 0;
  try {
    StabilizedObjective s(*f.objective, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "stability.step");
  }
}

}  // namespace
}  // namespace tricot::ident
