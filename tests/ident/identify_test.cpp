#include "tricot/ident/identify.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "analytic.hpp"
#include "tricot/core/error.hpp"

namespace tricot::ident {
namespace {

using test::AnalyticProblem;

// Noise-free data, default δ = 1e-5: LM stops once its relative steps fall below δ, a little
// short of the exact optimum.
constexpr double kRecovered = 1e-4;
// With δ = 1e-12 LM runs to round-off.
constexpr double kRecoveredTight = 1e-9;
constexpr double kRoundOff = 1e-11;  // one LM path run twice: differences from the last bits only

const Eigen::Vector3d kTruth(2.0, 0.7, 0.3);

TEST(Identify, DefaultOptionsAreValid) { EXPECT_NO_THROW(IdentifyOptions{}.validate()); }

TEST(Identify, RejectsOutOfRangeOptionsNamingTheKey) {
  IdentifyOptions o;
  o.delta = 0;
  try {
    o.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "identify.delta");
  }
  o = {};
  o.fd_step = 1;
  EXPECT_THROW(o.validate(), InputError);
}

TEST(Identify, RecoversANoiseFreeCurveFromThreeStarts) {
  for (const Eigen::Vector3d& factor :
       {Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d(2, 2, 2), Eigen::Vector3d(0.5, 2, 1.5)}) {
    const AnalyticProblem p = test::curve_fit(kTruth, kTruth.cwiseProduct(factor));
    const IdentifyResult r = identify(p);
    ASSERT_TRUE(r.converged()) << r.message;
    EXPECT_TRUE(r.stability_passed);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.parameters(k) / kTruth(k), 1.0, kRecovered) << factor.transpose();
    EXPECT_LT(r.objective, 1e-8);
    EXPECT_GT(r.iterations, 1);
    EXPECT_EQ(r.history.front().iteration, 0);
    EXPECT_EQ(r.history.front().parameters, kTruth.cwiseProduct(factor));
    EXPECT_LE(r.history.back().objective, r.history.front().objective);
  }
}

TEST(Identify, RecoversTheTruthToRoundOffWithATightDelta) {
  const AnalyticProblem p = test::curve_fit(kTruth, kTruth * 0.5);
  IdentifyOptions o;
  o.delta = 1e-12;
  o.epsilon = 0;
  const IdentifyResult r = identify(p, o);
  ASSERT_TRUE(r.converged()) << r.message;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.parameters(k) / kTruth(k), 1.0, kRecoveredTight);
}

TEST(Identify, FiniteDifferenceModeConvergesToTheSameAnswer) {
  const AnalyticProblem p = test::curve_fit(kTruth, Eigen::Vector3d(1.5, 1.0, 0.2));
  IdentifyOptions o;
  o.jacobian = JacobianMode::finite_difference;
  o.difference = Difference::central;
  const IdentifyResult r = identify(p, o);
  ASSERT_TRUE(r.converged()) << r.message;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.parameters(k) / kTruth(k), 1.0, kRecovered);
  EXPECT_EQ(r.jacobian, JacobianMode::finite_difference);
  // Each Jacobian costs 2n trial evaluations on top of the LM trials.
  EXPECT_GE(r.evaluations, r.jacobian_evaluations * 6);
}

TEST(Identify, StopsOnEpsilonWhenTheObjectiveIsBelowIt) {
  const AnalyticProblem p = test::curve_fit(kTruth, kTruth * 0.8);
  IdentifyOptions o;
  o.epsilon = 1e-4;
  o.stability_test = false;
  const IdentifyResult r = identify(p, o);
  EXPECT_EQ(r.termination, Termination::objective_below_epsilon) << r.message;
  EXPECT_LT(r.objective, 1e-4);
  EXPECT_GT(r.history[r.history.size() - 2].objective, 1e-4);  // the step before was not yet below ε
}

TEST(Identify, ReportsOneProgressLinePerIteration) {
  const AnalyticProblem p = test::curve_fit(kTruth, kTruth * 0.6);
  int reports = 0;
  std::string last;
  Reporter rep;
  rep.progress = [&](const Progress& pr) {
    ++reports;
    last = pr.detail;
    EXPECT_EQ(pr.stage, "identify");
  };
  IdentifyOptions o;
  o.stability_test = false;
  const IdentifyResult r = identify(p, o, rep);
  EXPECT_EQ(reports, r.iterations + 1);  // iteration 0 (the start) and every LM iteration
  EXPECT_NE(last.find("tau = "), std::string::npos);
}

// A problem with a local minimum near a = 1.001 (f ≈ 5e-5) and the global one at a = 1.1 (f = 0),
// separated by a barrier: LM started at 0.9 stops in the local one; the stability test with
// η = 0.1 probes a·1.1 ≈ 1.1, where f is lower, and restarts from there.
AnalyticProblem two_minima() {
  auto model = [](const Eigen::VectorXd& J) {
    const double a = J(0);
    return Eigen::Vector2d(10 * (a - 1) * (a - 1.1), 0.1 * (a - 1.1)).eval();
  };
  auto derivative = [](const Eigen::VectorXd& J) {
    const double a = J(0);
    Eigen::MatrixXd D(2, 1);
    D << 10 * (2 * a - 2.1), 0.1;
    return D;
  };
  // σ = 1 keeps the residuals unscaled: f = ½(r1² + r2²)/2.
  return AnalyticProblem({Parameter{"a", 0.9}}, model, derivative, Eigen::Vector2d::Zero(), 1.0);
}

TEST(Identify, StabilityTestRestartsFromABetterPerturbation) {
  const AnalyticProblem p = two_minima();
  IdentifyOptions o;
  o.stability_test = false;
  const IdentifyResult local = identify(p, o);
  ASSERT_TRUE(local.converged()) << local.message;
  EXPECT_NEAR(local.parameters(0), 1.0, 0.01);  // trapped in the local minimum

  o.stability_test = true;
  o.stability_eta = 0.1;
  const IdentifyResult global = identify(p, o);
  ASSERT_TRUE(global.converged()) << global.message;
  EXPECT_TRUE(global.stability_passed);
  EXPECT_GE(global.restarts, 1);
  EXPECT_NEAR(global.parameters(0), 1.1, 1.1 * kRecovered);
  EXPECT_LT(global.objective, local.objective);

  o.stability_eta = 0.03;  // a probe too small to cross the barrier: no restart
  EXPECT_EQ(identify(p, o).restarts, 0);
}

// A stability trial that a lower bound of f without the model (Problem::lower_bound: the stability
// barrier) puts at f* or above cannot beat f*: it is not evaluated, and the run is the same.
TEST(Identify, StabilityTrialsBoundedAboveTheOptimumAreNotEvaluated) {
  AnalyticProblem p = two_minima();
  IdentifyOptions o;
  o.stability_eta = 0.1;
  const IdentifyResult all = identify(p, o);
  // f = (r1² + r2²)/4 ≥ r1²/4: a true lower bound. At the local minimum (a ≈ 1.001, f* ≈ 5e-5) it
  // puts the trial a·0.9 at f ≥ 0.0097 and leaves a·1.1 (f ≈ 3e-7 there) to evaluate; at the global
  // minimum (f* ≈ 0) both trials are bounded above it.
  p.bound = [](const Eigen::VectorXd& J) {
    const double r1 = 10 * (J(0) - 1) * (J(0) - 1.1);
    return r1 * r1 / 4;
  };
  const int calls_before = p.calls;
  const IdentifyResult bounded = identify(p, o);
  EXPECT_EQ(all.skipped_evaluations, 0);
  EXPECT_EQ(bounded.skipped_evaluations, 3);
  EXPECT_EQ(bounded.evaluations, all.evaluations - 3);
  EXPECT_EQ(p.calls - calls_before, bounded.evaluations);
  EXPECT_EQ(bounded.restarts, all.restarts);
  EXPECT_EQ(bounded.restarts, 1);
  EXPECT_TRUE(bounded.stability_passed);
  EXPECT_EQ(bounded.parameters, all.parameters);  // the same run, bit for bit
  EXPECT_EQ(bounded.objective, all.objective);
}

// LM's steps are cut where the part of f that needs no FE (the barrier, Problem::lower_bound) would
// grow by more than barrier_growth · f at the accepted point. r = (a − 3, 10·max(0, a − 2)): the data
// pull a to 3, the barrier holds it at a* = 203/101. From a = 0 the barrier's row is zero and LM's
// model does not see it: its undamped step lands at a = 3, where the barrier alone is 25 (f(0) =
// 2.25); cut, the step stops where the barrier reaches 1 % of f(0), at a = 2.03, and LM goes on
// from there with the row in its model.
TEST(Identify, StepsAreCutWhereTheBarrierWouldGrowMoreThanAllowed) {
  const auto barrier = [](double a) {
    const double b = 10 * std::max(0.0, a - 2);
    return b * b / 4;  // its share of f = (r1² + r2²)/4
  };
  double worst = 0;  // the largest barrier share among the points evaluated
  auto model = [&](const Eigen::VectorXd& J) {
    worst = std::max(worst, barrier(J(0)));
    return Eigen::Vector2d(J(0), 10 * std::max(0.0, J(0) - 2)).eval();
  };
  auto derivative = [](const Eigen::VectorXd& J) {
    Eigen::MatrixXd D(2, 1);
    D << 1, J(0) > 2 ? 10 : 0;
    return D;
  };
  AnalyticProblem p({Parameter{"a", 0.0, 1.0}}, model, derivative, Eigen::Vector2d(3, 0), 1.0);
  p.bound = [&](const Eigen::VectorXd& J) { return barrier(J(0)); };
  IdentifyOptions o;
  o.initial_trust_region_radius = 1e4;  // the undamped Gauss–Newton step
  o.stability_test = false;
  o.barrier_growth = 0;
  const IdentifyResult plain = identify(p, o);
  const double plain_worst = worst;
  worst = 0;
  o.barrier_growth = 0.01;
  const IdentifyResult cut = identify(p, o);
  ASSERT_TRUE(plain.converged() && cut.converged()) << plain.message << cut.message;
  EXPECT_NEAR(plain.parameters(0), 203.0 / 101, 1e-4);
  EXPECT_NEAR(cut.parameters(0), 203.0 / 101, 1e-4);
  EXPECT_GT(plain_worst, 20);             // ~25: the step to a ≈ 3 (radius 1e4: nearly undamped)
  EXPECT_NEAR(worst, 0.01 * 2.25, 1e-9);  // the first step's end, cut to 1 % of f(0) to 2⁻⁴⁰
  EXPECT_LT(cut.evaluations, plain.evaluations);
}

TEST(Identify, RejectsATrialWhereTheModelFailsAndGoesOn) {
  // r = a² − 4, truth a = 2; from a = 1 the Gauss–Newton step lands at 2.5, where the model fails.
  auto model = [](const Eigen::VectorXd& J) { return Eigen::VectorXd::Constant(1, J(0) * J(0)); };
  auto derivative = [](const Eigen::VectorXd& J) { return Eigen::MatrixXd::Constant(1, 1, 2 * J(0)); };
  AnalyticProblem p({Parameter{"a", 1.0}}, model, derivative, Eigen::VectorXd::Constant(1, 4.0), 1.0);
  p.fails = [](const Eigen::VectorXd& J) { return J(0) > 2.2 && J(0) < 3; };
  IdentifyOptions o;
  o.initial_trust_region_radius = 1e4;  // an undamped first step, straight into the failing region
  const IdentifyResult r = identify(p, o);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_GE(r.failed_evaluations, 1);
  EXPECT_NEAR(r.parameters(0), 2.0, 2 * kRecovered);
}

TEST(Identify, AModelThatFailsAtTheStartIsATerminationNotAnException) {
  AnalyticProblem p = test::curve_fit(kTruth, kTruth);
  p.fails = [](const Eigen::VectorXd&) { return true; };
  const IdentifyResult r = identify(p);
  EXPECT_EQ(r.termination, Termination::fe_failure);
  EXPECT_FALSE(r.converged());
  EXPECT_NE(r.message.find("fails here"), std::string::npos) << r.message;
}

TEST(Identify, AZeroStartWithoutAScaleThrowsNamingTheParameter) {
  AnalyticProblem p({Parameter{"A", 1.0}, Parameter{"tau", 0.0}, Parameter{"B", 0.3}}, test::curve,
                    test::curve_derivative, test::curve(kTruth));
  try {
    identify(p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "parameters.tau.scale");
  }
}

TEST(Identify, AZeroStartWithAScaleIsIdentified) {
  std::vector<Parameter> params = test::curve_parameters(Eigen::Vector3d(1.5, 0.5, 0.0));
  params[2].scale = 0.1;
  AnalyticProblem p(params, test::curve, test::curve_derivative, test::curve(kTruth));
  const IdentifyResult r = identify(p);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_NEAR(r.parameters(2), kTruth(2), kRecovered * kTruth(2));
}

TEST(Identify, KeepsParametersWithinTheirBounds) {
  std::vector<Parameter> params = test::curve_parameters(Eigen::Vector3d(1.0, 0.5, 0.1));
  params[0].upper = 1.8;  // the truth (2.0) lies beyond
  AnalyticProblem p(params, test::curve, test::curve_derivative, test::curve(kTruth));
  const IdentifyResult r = identify(p);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_LE(r.parameters(0), 1.8);
  EXPECT_NEAR(r.parameters(0), 1.8, 1e-6);  // the constrained optimum sits on the bound
}

// A linear model y = A J with two strongly coupled columns (cos 0.9), J0 ≥ 0: the bounded problems of
// the active set, whose answers are closed forms.
Eigen::MatrixXd coupled_columns() {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(4, 2);
  A.col(0) << 1, 0, 0.5, 0;
  A.col(1) << 0.9, std::sqrt(1 - 0.81), 0.5, 0.1;
  return A;
}

AnalyticProblem coupled_linear(const Eigen::Vector2d& truth, const Eigen::Vector2d& start) {
  const Eigen::MatrixXd A = coupled_columns();
  std::vector<Parameter> params{Parameter{"p", start(0)}, Parameter{"q", start(1)}};
  params[0].lower = 0;
  params[0].scale = params[1].scale = 1;
  return AnalyticProblem(
      params, [A](const Eigen::VectorXd& J) { return (A * J).eval(); }, [A](const Eigen::VectorXd&) { return A; },
      A * truth);
}

TEST(Identify, HoldsAVariableOnItsBoundWhereFDecreasesOutOfTheBox) {
  // Unconstrained optimum (−1, 1), outside the box. The constrained one: p = 0 and q the 1-D least
  // squares of the second column against the data, q = a_q·y / |a_q|² (f decreases out of the box there:
  // the KKT multiplier of p ≥ 0 is positive).
  const AnalyticProblem p = coupled_linear(Eigen::Vector2d(-1, 1), Eigen::Vector2d(0.5, 0.5));
  const Eigen::MatrixXd A = coupled_columns();
  const Eigen::VectorXd y = A * Eigen::Vector2d(-1, 1);
  const double q = A.col(1).dot(y) / A.col(1).squaredNorm();
  ASSERT_GT(A.col(0).dot(A.col(1) * q - y), 0);  // f decreases out of the box at the answer
  std::vector<std::string> log;
  Reporter rep;
  rep.log = [&](const std::string& line) { log.push_back(line); };
  IdentifyOptions o;
  o.active_set = true;
  o.delta = 1e-12, o.function_tolerance = 0;  // to round-off
  const IdentifyResult r = identify(p, o, rep);
  ASSERT_TRUE(r.converged()) << r.brief_report();
  EXPECT_EQ(r.parameters(0), 0.0);
  EXPECT_NEAR(r.parameters(1), q, 1e-10) << r.brief_report();
  // LM steps in q alone once p is held: 7 iterations to round-off. Ceres's projected steps alone (stop
  // 21): not converged after 200 iterations and 335 evaluations, f 0.4 % above the minimum.
  EXPECT_LE(r.iterations, 8);
  EXPECT_TRUE(std::any_of(log.begin(), log.end(),
                          [](const std::string& l) { return l.find("held at its bound") != std::string::npos; }));
}

// From a start on the bound, LM's first step is projected back onto it and accepted (q improves):
// p is held there at once, not after a rejected step, and LM steps in q alone. Ceres's model would
// otherwise promise what the projected steps cannot give, step after step (the §4 campaign's 150 mm
// identification crawled 200 iterations so, with a6 on its bound).
TEST(Identify, HoldsAVariableThatAnAcceptedStepLeftOnItsBound) {
  const AnalyticProblem p = coupled_linear(Eigen::Vector2d(-1, 1), Eigen::Vector2d(0, 5));
  const Eigen::MatrixXd A = coupled_columns();
  const Eigen::VectorXd y = A * Eigen::Vector2d(-1, 1);
  const double q = A.col(1).dot(y) / A.col(1).squaredNorm();
  std::vector<std::string> log;
  Reporter rep;
  rep.log = [&](const std::string& line) { log.push_back(line); };
  IdentifyOptions o;
  o.active_set = true;
  o.stability_test = false;
  o.delta = 1e-12, o.function_tolerance = 0;
  const IdentifyResult r = identify(p, o, rep);
  ASSERT_TRUE(r.converged()) << r.brief_report();
  EXPECT_EQ(r.parameters(0), 0.0);
  EXPECT_NEAR(r.parameters(1), q, 1e-10) << r.brief_report();
  ASSERT_GE(r.history.size(), 2u);
  EXPECT_EQ(r.history[1].parameters(0), 0.0);  // the first accepted step: projected onto p = 0
  EXPECT_TRUE(std::any_of(log.begin(), log.end(),
                          [](const std::string& l) { return l.find("held at its bound") != std::string::npos; }));
  EXPECT_EQ(r.failed_evaluations, 0);
  // 6 iterations, 8 evaluations. Held only after a rejected step (stop 23), p never was: 74 projected
  // steps, each accepted, and LM stopped on δ with q short of its answer (f 0.4913).
  EXPECT_LE(r.iterations, 8);
}

TEST(Identify, ReleasesAHeldVariableWhenFDecreasesIntoTheBoxAgain) {
  // A run that held p on its bound at (0, 5) (its checkpoint says so) goes on in q alone; where f
  // decreases into the box along p (the coupling: at q ≈ 1.9 the residual pulls p up), p is released
  // and LM reaches the interior optimum (1, 1) of zero residual.
  const AnalyticProblem p = coupled_linear(Eigen::Vector2d(1, 1), Eigen::Vector2d(0, 5));
  Checkpoint held;
  held.names = {"p", "q"};
  held.scales = Eigen::Vector2d(1, 1);
  held.x = held.parameters = Eigen::Vector2d(0, 5);
  held.trust_region_radius = 10;
  held.held = {0};
  std::vector<std::string> log;
  Reporter rep;
  rep.log = [&](const std::string& line) { log.push_back(line); };
  IdentifyOptions o;
  o.active_set = true;
  o.delta = 1e-12;
  o.epsilon = 0;
  o.resume_from = held;
  const IdentifyResult r = identify(p, o, rep);
  ASSERT_TRUE(r.converged()) << r.brief_report();
  EXPECT_NEAR(r.parameters(0), 1.0, 1e-9);
  EXPECT_NEAR(r.parameters(1), 1.0, 1e-9);
  EXPECT_TRUE(std::any_of(log.begin(), log.end(), [&](const std::string& l) {
    return l.find("released from its bound (f decreases into the box): p") != std::string::npos;
  }));
}

TEST(Identify, ResumedFromACheckpointReachesTheSameAnswer) {
  const AnalyticProblem p = test::curve_fit(kTruth, Eigen::Vector3d(1.2, 1.4, 0.5));
  std::vector<Checkpoint> saved;
  IdentifyOptions o;
  o.on_checkpoint = [&](const Checkpoint& c) { saved.push_back(c); };
  const IdentifyResult full = identify(p, o);
  ASSERT_TRUE(full.converged()) << full.message;
  ASSERT_GE(saved.size(), 4u);
  EXPECT_EQ(saved.front().iterations, 0);

  // A run killed after its third accepted step, continued from the checkpoint it left.
  IdentifyOptions resume;
  resume.resume_from = saved[3];
  const IdentifyResult rest = identify(p, resume);
  EXPECT_EQ(rest.termination, full.termination);
  // LM's state is all in the checkpoint: the same path to round-off. Not bit for bit: Eigen's AVX
  // code peels a vector's first entries to a 32-byte boundary, and the heap is 16-byte aligned
  // (CMakeLists.txt), so the last bit of an entry can depend on where its vector was allocated.
  EXPECT_LT((rest.parameters - full.parameters).cwiseAbs().maxCoeff(), kRoundOff * full.parameters.norm());
  EXPECT_EQ(rest.iterations, full.iterations);
  EXPECT_EQ(rest.history.size(), full.history.size());
  // The resumed run evaluates the checkpoint's point once more (the killed one had it in memory).
  EXPECT_EQ(rest.evaluations, full.evaluations + 1);
}

// A kill at any moment resumes from the last checkpoint written before it; resuming from every
// checkpoint of a run is resuming from every kill point: during LM, after its last accepted step
// (ε/δ already met: phase stability), during or after a stability test and its restart, and after
// the end (phase done: only the uncertainty is left).
constexpr double kResumedAnswer = 1e-10;  // issue 14: the uninterrupted answer to round-off

// `same_message`: false for a run to round-off, whose stopping message quotes a gradient of a few ulps
// (the last bit depends on allocation alignment: ResumedFromACheckpointReachesTheSameAnswer).
void expect_every_checkpoint_resumes_to(const Problem& p, const IdentifyOptions& base, bool same_message = true) {
  std::vector<Checkpoint> saved;
  IdentifyOptions o = base;
  o.on_checkpoint = [&](const Checkpoint& c) { saved.push_back(c); };
  const IdentifyResult full = identify(p, o);
  ASSERT_TRUE(full.converged()) << full.message;
  ASSERT_EQ(saved.back().phase, Phase::done);
  for (std::size_t i = 0; i < saved.size(); ++i) {
    IdentifyOptions resume = base;
    resume.resume_from = saved[i];
    const IdentifyResult rest = identify(p, resume);
    SCOPED_TRACE("resumed from checkpoint " + std::to_string(i) + " (phase " + to_string(saved[i].phase) +
                 ", iteration " + std::to_string(saved[i].iterations) + ")");
    EXPECT_EQ(rest.termination, full.termination);
    if (same_message) {
      EXPECT_EQ(rest.message, full.message);
    }
    EXPECT_EQ(rest.iterations, full.iterations);
    EXPECT_EQ(rest.restarts, full.restarts);
    EXPECT_EQ(rest.stability_passed, full.stability_passed);
    EXPECT_EQ(rest.history.size(), full.history.size());
    EXPECT_EQ(rest.start, full.start);
    for (Eigen::Index k = 0; k < full.parameters.size(); ++k)
      EXPECT_NEAR(rest.parameters(k), full.parameters(k), kResumedAnswer * std::abs(full.parameters(k)));
  }
}

TEST(Identify, ResumedFromAnyCheckpointReachesTheUninterruptedAnswerWithTheSameIterations) {
  const AnalyticProblem p = test::curve_fit(kTruth, Eigen::Vector3d(1.2, 1.4, 0.5));
  expect_every_checkpoint_resumes_to(p, {});  // stops on ε (eq. 2)
  IdentifyOptions o;
  o.epsilon = 0;  // stops on δ: eq. (3) or Ceres's step test on a trial step
  expect_every_checkpoint_resumes_to(p, o);
  o.delta = 1e-12;  // to round-off
  expect_every_checkpoint_resumes_to(p, o, /*same_message=*/false);
  // With a bound Ceres makes its step test from the first trial of a solve, resumed or not.
  auto params = test::curve_parameters(Eigen::Vector3d(1.2, 1.4, 0.5));
  params[0].upper = 1.8;
  const AnalyticProblem bounded(params, test::curve, test::curve_derivative, test::curve(kTruth));
  o.delta = 1e-5;
  expect_every_checkpoint_resumes_to(bounded, o);
}

TEST(Identify, ResumedAcrossHoldsAndReleasesOfTheActiveSetReachesTheUninterruptedAnswer) {
  IdentifyOptions o;
  o.active_set = true;
  o.delta = 1e-9;
  o.epsilon = 0;
  expect_every_checkpoint_resumes_to(coupled_linear(Eigen::Vector2d(-1, 1), Eigen::Vector2d(0.5, 0.5)), o, false);
}

TEST(Identify, ResumedInsideTheStabilityTestAndItsRestartReachesTheUninterruptedAnswer) {
  const AnalyticProblem p = two_minima();
  IdentifyOptions o;
  o.stability_eta = 0.1;  // one restart (StabilityTestRestartsFromABetterPerturbation)
  std::vector<Phase> phases;
  o.on_checkpoint = [&](const Checkpoint& c) { phases.push_back(c.phase); };
  ASSERT_GE(identify(p, o).restarts, 1);
  EXPECT_GE(std::count(phases.begin(), phases.end(), Phase::stability), 2);  // before and after the restart
  o.on_checkpoint = {};
  expect_every_checkpoint_resumes_to(p, o);
}

TEST(Identify, TheCheckpointAfterTheLastAcceptedStepSaysLmHasConverged) {
  const AnalyticProblem p = test::curve_fit(kTruth, Eigen::Vector3d(1.2, 1.4, 0.5));
  std::vector<Checkpoint> saved;
  IdentifyOptions o;
  o.on_checkpoint = [&](const Checkpoint& c) { saved.push_back(c); };
  const IdentifyResult full = identify(p, o);
  ASSERT_EQ(full.termination, Termination::objective_below_epsilon);
  // The first checkpoint at the final iteration is written after its ε test: phase stability.
  const auto last_lm =
      std::find_if(saved.begin(), saved.end(), [&](const Checkpoint& c) { return c.iterations == full.iterations; });
  ASSERT_NE(last_lm, saved.end());
  EXPECT_EQ(last_lm->phase, Phase::stability);
  EXPECT_EQ(last_lm->termination, Termination::objective_below_epsilon);
  EXPECT_EQ(saved.back().phase, Phase::done);
  EXPECT_TRUE(saved.back().stability_passed);
}

TEST(Identify, RefusesACheckpointOfAnotherProblem) {
  const AnalyticProblem p = test::curve_fit(kTruth, kTruth * 0.9);
  Checkpoint c;
  c.names = {"A", "tau"};
  IdentifyOptions o;
  o.resume_from = c;
  EXPECT_THROW(identify(p, o), InputError);
}

TEST(Identify, ReportsUncertaintyAtTheOptimum) {
  const AnalyticProblem p = test::curve_fit(kTruth, kTruth * 0.7);
  const IdentifyResult r = identify(p);
  ASSERT_EQ(r.uncertainty.std_error.size(), 3);
  EXPECT_TRUE(r.uncertainty.full_rank);
  EXPECT_GT(r.uncertainty.condition_number, 1);
  EXPECT_NEAR(r.uncertainty.least_identifiable.norm(), 1.0, 1e-12);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.uncertainty.correlation(k, k), 1.0, 1e-12);
}

}  // namespace
}  // namespace tricot::ident
