#include "tricot/ident/objective.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "testing/fd_check.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/response_surface.hpp"
#include "tricot/fem/rig.hpp"
#include "tricot/ident/identify.hpp"
#include "tricot/ident/synthetic.hpp"
#include "uniaxial.hpp"

namespace tricot::ident {
namespace {

using test::field_points;
using test::uniaxial;

// Newton converged to 1e-13 and central differences with h = 1e-6 (relative ~1e-5 of C_ij):
// truncation ~h², FE round-off ~1e-13/h.
constexpr double kFdAgreement = 1e-5;

const std::vector<fem::MooneyRivlinTerm> kTruth = fem::paper_mooney_rivlin_terms();

std::vector<Parameter> all_four(double factor = 1) {
  std::vector<Parameter> p;
  for (const auto& t : kTruth) p.push_back(Parameter{"C" + std::to_string(t.i) + std::to_string(t.j), factor * t.C});
  return p;
}

Experiment experiment_from(const fem::TestModel& model, const Eigen::Matrix2Xd& points, FieldKind kind) {
  const fem::SimulationResult sim = fem::simulate(model, fem::MooneyRivlin(kTruth));
  EXPECT_TRUE(sim.usable()) << sim.message;
  Experiment e;
  e.tests.push_back(measure(model, sim, points, {}, kind));
  return e;
}

ObjectiveOptions tight() {
  ObjectiveOptions o;
  o.solver.tolerance = 1e-13;
  return o;
}

void expect_jacobian_matches_fd(const Objective& objective) {
  Eigen::VectorXd J(4);
  J << 0.11, -0.022, 0.016, 0.0095;  // near the truth, not at it
  const Evaluation e = objective.evaluate(J, true);
  ASSERT_TRUE(e.ok) << e.message;
  ASSERT_EQ(e.jacobian.rows(), objective.residuals());
  auto r = [&](const Eigen::VectorXd& x) {
    const Evaluation ex = objective.evaluate(x, false);
    EXPECT_TRUE(ex.ok) << ex.message;
    return ex.r;
  };
  EXPECT_TRUE(tricot::test::JacobianMatches(r, J, e.jacobian, kFdAgreement, 1e-6));
  char err[32];
  std::snprintf(err, sizeof err, "%.2e", tricot::test::jacobian_error(r, J, e.jacobian, 1e-6));
  ::testing::Test::RecordProperty("jacobian_fd_error", err);
}

TEST(Objective, JacobianMatchesFiniteDifferencesForEdgeDisplacementAndCumulativeField) {
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::force);
  const Objective objective({model}, experiment_from(model, field_points(3, 4), FieldKind::cumulative),
                            fem::MooneyRivlin(kTruth), all_four(), tight());
  ASSERT_EQ(objective.data().groups().size(), 3u);  // edge displacement, u, v
  EXPECT_EQ(objective.data().groups()[0].kind, GroupKind::edge_displacement);
  expect_jacobian_matches_fd(objective);
}

TEST(Objective, JacobianMatchesFiniteDifferencesForEdgeForceAndIncrementalField) {
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::displacement);
  ObjectiveOptions o = tight();
  o.weights.field_uv = true;
  const Objective objective({model}, experiment_from(model, field_points(3, 4, 5), FieldKind::incremental),
                            fem::MooneyRivlin(kTruth), all_four(), o);
  ASSERT_EQ(objective.data().groups().size(), 2u);  // edge force, uv
  EXPECT_EQ(objective.data().groups()[1].kind, GroupKind::field_uv);
  expect_jacobian_matches_fd(objective);
}

// Two repeats of one strip, the second a stiffer specimen (its force ×1.2), with the second's force
// scale identified (docs/theory.md §2): the objective is zero at the law's truth and k = 1.2, its
// Jacobian (the scale's column: the law's force) matches central differences, and LM finds both from a
// start 10 % off.
struct Repeats {
  std::vector<fem::TestModel> models;
  Experiment experiment;
};
Repeats two_repeats(double k) {
  Repeats r;
  for (const char* name : {"a", "b"}) {
    fem::TestModel m = uniaxial(2, 4, 3, fem::GripControl::displacement);
    m.name = name;
    r.models.push_back(m);
    Experiment e = experiment_from(m, field_points(3, 4), FieldKind::cumulative);
    e.tests[0].name = name;
    if (std::string(name) == "b")
      for (double& f : e.tests[0].edge_force) f *= k;
    r.experiment.tests.push_back(e.tests[0]);
  }
  return r;
}

TEST(Objective, AForceScaleIsZeroAtItsTruthAndItsJacobianMatchesFiniteDifferences) {
  const Repeats rep = two_repeats(1.2);
  std::vector<Parameter> p = all_four();
  p.push_back(Parameter{"b.force_scale"});
  const Objective objective(rep.models, rep.experiment, fem::MooneyRivlin(kTruth), p, tight());
  ASSERT_EQ(objective.law_parameters(), 4);
  EXPECT_EQ(objective.parameters()[4].start, 1.0);  // a NaN start is 1
  Eigen::VectorXd J(5);
  J << 0.1, -0.025, 0.015, 0.01, 1.2;
  const Evaluation at_truth = objective.evaluate(J, false);
  ASSERT_TRUE(at_truth.ok) << at_truth.message;
  EXPECT_LT(at_truth.objective(), 1e-20);  // round-off of k × y
  EXPECT_EQ(objective.force_scale(J, 1), 1.2);
  EXPECT_EQ(objective.force_scale(J, 0), 1.0);
  J << 0.11, -0.022, 0.016, 0.0095, 1.1;
  const Evaluation e = objective.evaluate(J, true);
  ASSERT_TRUE(e.ok) << e.message;
  auto r = [&](const Eigen::VectorXd& x) {
    const Evaluation ex = objective.evaluate(x, false);
    EXPECT_TRUE(ex.ok) << ex.message;
    return ex.r;
  };
  EXPECT_TRUE(tricot::test::JacobianMatches(r, J, e.jacobian, kFdAgreement, 1e-6));
  // The field rows do not depend on the scale: under a displacement-controlled grip the FE's
  // displacements are the law's whatever the forces' scale.
  for (const DataGroup& g : objective.data().groups()) {
    if (g.kind != GroupKind::edge_force || g.test == 0) {
      EXPECT_EQ(e.jacobian.col(4).segment(g.offset, g.size).norm(), 0.0) << g.name;
    }
  }
  // LM from 10 % off.
  std::vector<Parameter> off = p;
  for (std::size_t k = 0; k < 4; ++k) off[k].start = 1.1 * kTruth[k].C;
  off[4].start = 1.0;
  const Objective from_off(rep.models, rep.experiment, fem::MooneyRivlin(kTruth), off, tight());
  IdentifyOptions io;
  io.epsilon = 1e-20;
  io.delta = 1e-10;
  const IdentifyResult got = identify(from_off, io);
  ASSERT_TRUE(got.converged()) << got.message;
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_NEAR(got.parameters(Eigen::Index(k)), kTruth[k].C, 1e-6 * std::abs(kTruth[k].C));
  EXPECT_NEAR(got.parameters(4), 1.2, 1e-6);
}

TEST(Objective, AForceScaleNeedsADisplacementGripAndAnUnscaledTestBeside) {
  const Repeats rep = two_repeats(1.0);
  std::vector<Parameter> both = all_four();
  both.push_back(Parameter{"a.force_scale"});
  both.push_back(Parameter{"b.force_scale"});
  try {  // nothing sets the law's scale
    Objective(rep.models, rep.experiment, fem::MooneyRivlin(kTruth), both);
    FAIL();
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().key, "parameters");
    EXPECT_NE(std::string(err.what()).find("every test's force is scaled"), std::string::npos) << err.what();
  }
  const fem::TestModel force = uniaxial(2, 4, 3, fem::GripControl::force);
  std::vector<Parameter> p = all_four();
  p.push_back(Parameter{"uniaxial.force_scale"});
  try {
    Objective({force}, experiment_from(force, field_points(3, 4), FieldKind::cumulative), fem::MooneyRivlin(kTruth), p);
    FAIL();
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().key, "parameters.uniaxial.force_scale");
    EXPECT_NE(std::string(err.what()).find("displacement-controlled"), std::string::npos) << err.what();
  }
}

TEST(Objective, IsZeroAtTheTruthOnTheSameMesh) {
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::force);
  const Objective objective({model}, experiment_from(model, field_points(3, 4, 5), FieldKind::incremental),
                            fem::MooneyRivlin(kTruth), all_four(), tight());
  const Evaluation e = objective.evaluate(Eigen::Vector4d(0.1, -0.025, 0.015, 0.01), false);
  ASSERT_TRUE(e.ok);
  EXPECT_LT(e.objective(), 1e-24);
}

TEST(Objective, StepWeightsScaleEveryRowOfTheirStep) {
  // Per-step weights ω_k (a domain-weighted identification): every row of step k, in every group of
  // the test, is the unweighted row times √ω_k, its Jacobian row too.
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::displacement);
  const Experiment plain = experiment_from(model, field_points(3, 4), FieldKind::cumulative);
  Experiment weighted = plain;
  weighted.tests[0].step_weight = {1.0, 0.25, 0.0};
  const Objective a({model}, plain, fem::MooneyRivlin(kTruth), all_four(), tight());
  const Objective b({model}, weighted, fem::MooneyRivlin(kTruth), all_four(), tight());
  const Eigen::Vector4d J(0.11, -0.022, 0.016, 0.0095);
  const Evaluation ea = a.evaluate(J, true), eb = b.evaluate(J, true);
  ASSERT_TRUE(ea.ok && eb.ok);
  ASSERT_EQ(a.data().groups().size(), 3u);  // force, u, v
  for (const DataGroup& g : a.data().groups()) {
    const int per_step = g.size / 3;
    for (int k = 0; k < 3; ++k) {
      const double s = std::sqrt(weighted.tests[0].step_weight[k]);
      const auto rows = Eigen::seqN(g.offset + k * per_step, per_step);
      if (s == 0) {
        EXPECT_EQ(eb.r(rows).norm(), 0.0) << g.name;
        EXPECT_EQ(eb.jacobian(rows, Eigen::all).norm(), 0.0) << g.name;
      } else {
        EXPECT_TRUE(eb.r(rows).isApprox(s * ea.r(rows), 1e-14)) << g.name << " step " << k;
        EXPECT_TRUE(eb.jacobian(rows, Eigen::all).isApprox(s * ea.jacobian(rows, Eigen::all), 1e-14)) << g.name;
      }
    }
  }
  weighted.tests[0].step_weight = {1.0, 1.0};  // one per step
  EXPECT_THROW(Objective({model}, weighted, fem::MooneyRivlin(kTruth), all_four()), InputError);
  weighted.tests[0].step_weight = {1.0, -1.0, 1.0};
  EXPECT_THROW(Objective({model}, weighted, fem::MooneyRivlin(kTruth), all_four()), InputError);
}

TEST(Objective, PointsOutsideTheSpecimenAreAnInputErrorCountingThem) {
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::force);
  Experiment e = experiment_from(model, field_points(3, 4), FieldKind::cumulative);
  e.tests[0].source = "points.csv";
  e.tests[0].points(0, 5) = 12;  // beyond the quarter's width (10 mm)
  e.tests[0].points(1, 7) = -1;  // below the axis of symmetry
  try {
    Objective({model}, e, fem::MooneyRivlin(kTruth), all_four());
    FAIL();
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().file, "points.csv");
    EXPECT_EQ(err.where().key, "experiment.uniaxial.points");
    const std::string what = err.what();
    EXPECT_NE(what.find("2 of 12 points"), std::string::npos) << what;
    EXPECT_NE(what.find("id 5 at (12, "), std::string::npos) << what;
  }
}

TEST(Objective, RejectsAParameterTheLawDoesNotHave) {
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::force);
  try {
    Objective({model}, experiment_from(model, field_points(3, 4), FieldKind::cumulative), fem::MooneyRivlin(kTruth),
              {Parameter{"C11", 0.1}});
    FAIL();
  } catch (const InputError& err) {
    EXPECT_EQ(err.where().key, "parameters.C11");
    EXPECT_NE(std::string(err.what()).find("C10, C20, C21, C03"), std::string::npos) << err.what();
  }
}

TEST(Objective, RejectsDataWhoseStepsDifferFromTheModel) {
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::force);
  Experiment e = experiment_from(model, field_points(3, 4), FieldKind::cumulative);
  fem::TestModel other = model;
  other.loads.back() *= 1.01;
  EXPECT_THROW(Objective({other}, e, fem::MooneyRivlin(kTruth), all_four()), InputError);
}

TEST(Objective, ANaNStartTakesTheLawsValue) {
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::force);
  const Objective objective({model}, experiment_from(model, field_points(3, 4), FieldKind::cumulative),
                            fem::MooneyRivlin(kTruth), {Parameter{"C20"}});
  EXPECT_EQ(objective.parameters()[0].start, -0.025);
}

TEST(Objective, ADivergingTrialIsAFailedEvaluationNotAnException) {
  const fem::TestModel model = uniaxial(2, 4, 3, fem::GripControl::force);
  const Objective objective({model}, experiment_from(model, field_points(3, 4), FieldKind::cumulative),
                            fem::MooneyRivlin(kTruth), all_four());
  // A law without stiffness: the FE cannot even start.
  const Evaluation e = objective.evaluate(Eigen::Vector4d::Zero(), false);
  EXPECT_FALSE(e.ok);
  EXPECT_NE(e.message.find("test uniaxial"), std::string::npos) << e.message;
}

/// Four small rig tests (docs/theory.md §6) with data from the reference knit and `paper14` to identify: a
/// non-symmetric tangent (the simplicial LU), guides, ties and sensitivities, as in the §4 campaign.
struct RigCampaign {
  std::vector<fem::TestModel> models;
  Experiment data;
  fem::ResponseSurface law = fem::ResponseSurface::preset("paper14", 0.05);
  std::vector<Parameter> parameters;
};
RigCampaign rig_campaign() {
  RigCampaign c;
  const fem::ReferenceFabric truth;
  for (auto [pull, transverse] : {std::pair{fem::PullDirection::wale, 0.0},
                                  {fem::PullDirection::wale, 0.3},
                                  {fem::PullDirection::course, 0.0},
                                  {fem::PullDirection::course, 0.2}}) {
    fem::RigOptions o;
    o.name = std::string(fem::to_string(pull)) + "-" + std::to_string(static_cast<int>(100 * transverse));
    o.pull = pull, o.transverse_strain = transverse, o.pull_strain = 0.3, o.steps = 4, o.nx = 4, o.ny = 4;
    const fem::TestModel m = fem::make_rig_test(o);
    const fem::SimulationResult r = fem::simulate(m, truth);
    EXPECT_TRUE(r.usable()) << r.message;
    c.models.push_back(m);
    c.data.tests.push_back(measure(m, r, field_points(3, 3, 20) * 1.5));
  }
  Eigen::VectorXd J = Eigen::VectorXd::Zero(14);
  J(0) = 0.25, J(8) = 0.06, J(6) = 0.01, J(12) = 0.01;  // a1, c1, b1, d1: a stable start
  c.law.set_coefficients(J);
  for (const std::string& name : c.law.coefficient_names()) c.parameters.push_back(Parameter{name});
  return c;
}

// Issue 15: the tests of an evaluation run on threads, each with its own solver, and the result is
// the serial one bit for bit (each test's values land in their own rows; nothing is summed across
// threads).
TEST(Objective, ThreadsGiveTheSerialResidualsAndJacobianBitForBit) {
  const RigCampaign c = rig_campaign();
  Eigen::VectorXd J = c.law.coefficients();
  J(0) *= 1.1, J(8) *= 0.9;
  Evaluation serial;
  for (int threads : {1, 2, 4}) {
    ObjectiveOptions o;
    o.threads = threads;
    const Objective objective(c.models, c.data, c.law, c.parameters, o);
    const Evaluation e = objective.evaluate(J, true);
    ASSERT_TRUE(e.ok) << e.message;
    if (threads == 1) {
      serial = e;
      EXPECT_GT(e.jacobian.cwiseAbs().maxCoeff(), 0);
      continue;
    }
    ASSERT_EQ(e.r.size(), serial.r.size());
    EXPECT_TRUE((e.r.array() == serial.r.array()).all()) << threads << " threads";
    EXPECT_TRUE((e.jacobian.array() == serial.jacobian.array()).all()) << threads << " threads";
  }
}

// ObjectiveOptions::sensitivities_after: the sensitivities are added after the simulations
// (fem::add_sensitivities), so the residuals do not depend on whether the Jacobian was asked for, and a
// Jacobian asked for at a point evaluated before (LM's accepted trial) comes from its kept
// simulations: the same numbers, bit for bit, as asking for it at once; and the Jacobian of
// sensitivities with the solve to 1e-7 (the two runs' Newton paths differ within its tolerance).
TEST(Objective, AJacobianAskedForAfterTheValuesIsTheOneAskedForAtOnce) {
  const RigCampaign c = rig_campaign();
  Eigen::VectorXd J = c.law.coefficients();
  J(0) *= 1.1, J(8) *= 0.9;
  ObjectiveOptions o;
  o.sensitivities_after = true;
  const Objective at_once(c.models, c.data, c.law, c.parameters, o), after(c.models, c.data, c.law, c.parameters, o);
  const Objective inline_(c.models, c.data, c.law, c.parameters);
  EXPECT_TRUE(at_once.keeps_simulations());
  EXPECT_FALSE(inline_.keeps_simulations());
  const Evaluation d = inline_.evaluate(J, true);
  ASSERT_TRUE(d.ok) << d.message;
  const Evaluation a = at_once.evaluate(J, true);
  const Evaluation values = after.evaluate(J, false);
  const Evaluation b = after.evaluate(J, true);
  ASSERT_TRUE(a.ok && values.ok && b.ok) << a.message << values.message << b.message;
  EXPECT_TRUE((values.r.array() == a.r.array()).all());
  EXPECT_TRUE((b.r.array() == a.r.array()).all());
  ASSERT_EQ(b.jacobian.rows(), a.jacobian.rows());
  EXPECT_TRUE((b.jacobian.array() == a.jacobian.array()).all());
  EXPECT_GT(a.jacobian.cwiseAbs().maxCoeff(), 0);
  EXPECT_LT((d.jacobian - a.jacobian).cwiseAbs().maxCoeff(), 1e-7 * a.jacobian.cwiseAbs().maxCoeff());
}

// ObjectiveOptions::warm_start: an evaluation starts from the last one with a Jacobian (moved by its
// sensitivities). Its residuals and Jacobian are a cold evaluation's to the FE tolerance (Newton's
// 1e-10 of the reactions: 1e-8 here), with threads or without, after values-only evaluations too.
TEST(Objective, AWarmStartedEvaluationIsTheColdOneToTheSolversTolerance) {
  const RigCampaign c = rig_campaign();
  Eigen::VectorXd J = c.law.coefficients(), J2 = J;
  J2(0) *= 1.02, J2(8) *= 0.98, J2(1) += 0.01;
  ObjectiveOptions o;
  const Objective cold(c.models, c.data, c.law, c.parameters, o);
  o.warm_start = true;
  for (int threads : {1, 2}) {
    o.threads = threads;
    const Objective warm(c.models, c.data, c.law, c.parameters, o);
    ASSERT_TRUE(warm.evaluate(J, true).ok);
    ASSERT_TRUE(warm.evaluate(0.5 * (J + J2), false).ok);  // no Jacobian: not a start for the next
    const Evaluation w = warm.evaluate(J2, true), k = cold.evaluate(J2, true);
    ASSERT_TRUE(w.ok && k.ok) << w.message << k.message;
    EXPECT_LT((w.r - k.r).cwiseAbs().maxCoeff(), 1e-8 * k.r.cwiseAbs().maxCoeff()) << threads << " threads";
    EXPECT_LT((w.jacobian - k.jacobian).cwiseAbs().maxCoeff(), 1e-7 * k.jacobian.cwiseAbs().maxCoeff());
    EXPECT_FALSE((w.r.array() == k.r.array()).all());  // it did start elsewhere
  }
}

// evaluate() keeps its last Jacobian evaluation and gives it back at that point (the identifiability
// report at LM's answer costs no FE): never another point's. simulations(J) gives each test's run at
// J: the last evaluation's where it is at J, else fresh; both are fem::simulate's to the FE tolerance.
TEST(Objective, TheLastJacobianEvaluationAndItsSimulationsServeItsPointOnly) {
  const RigCampaign c = rig_campaign();
  Eigen::VectorXd J = c.law.coefficients(), J2 = J;
  J2(0) *= 1.02, J2(8) *= 0.98;
  ObjectiveOptions o;
  o.warm_start = true;
  const Objective objective(c.models, c.data, c.law, c.parameters, o);
  const Evaluation a = objective.evaluate(J, true), b = objective.evaluate(J2, true);
  ASSERT_TRUE(a.ok && b.ok) << a.message << b.message;
  const Evaluation b_again = objective.evaluate(J2, true), a_again = objective.evaluate(J, true);
  ASSERT_TRUE(b_again.ok && a_again.ok);
  EXPECT_TRUE((b_again.r.array() == b.r.array()).all() && (b_again.jacobian.array() == b.jacobian.array()).all());
  const double scale = a.r.cwiseAbs().maxCoeff();
  EXPECT_GT((a.r - b.r).cwiseAbs().maxCoeff(), 1e-4 * scale);        // the two points differ
  EXPECT_LT((a_again.r - a.r).cwiseAbs().maxCoeff(), 1e-8 * scale);  // J's evaluation, not J2's
  EXPECT_LT((a_again.jacobian - a.jacobian).cwiseAbs().maxCoeff(), 1e-7 * a.jacobian.cwiseAbs().maxCoeff());

  // The last Jacobian evaluation is now at J: simulations(J) are its runs, simulations(J2) fresh ones.
  for (const Eigen::VectorXd& at : {J, J2}) {
    const std::vector<fem::SimulationResult> sims = objective.simulations(at);
    ASSERT_EQ(sims.size(), c.models.size());
    const auto law = objective.law_at(at);
    for (std::size_t t = 0; t < c.models.size(); ++t) {
      const fem::SimulationResult ref = fem::simulate(c.models[t], *law);
      ASSERT_TRUE(sims[t].usable() && ref.usable()) << sims[t].message;
      ASSERT_EQ(sims[t].steps.size(), ref.steps.size());
      for (std::size_t k = 0; k < ref.steps.size(); ++k)
        EXPECT_NEAR(sims[t].steps[k].edge_force, ref.steps[k].edge_force, 1e-8 * std::abs(ref.steps.back().edge_force))
            << c.models[t].name << " step " << k;
    }
  }
}

// Above fem::kSensitivitiesAfterBelow unknowns a test's sensitivities cost a factorization per step
// more afterwards than with the solve: the objective then keeps to the solve's.
TEST(Objective, AddsNoSensitivitiesAfterwardsOnLargeMeshes) {
  fem::RigOptions r;
  r.name = "large", r.transverse_strain = 0.1, r.pull_strain = 0.1, r.steps = 2, r.nx = 20, r.ny = 20;
  const fem::TestModel m = fem::make_rig_test(r);
  ASSERT_GE(m.mesh.dofs(), fem::kSensitivitiesAfterBelow);
  const fem::ReferenceFabric truth;
  const fem::SimulationResult s = fem::simulate(m, truth);
  ASSERT_TRUE(s.usable()) << s.message;
  Experiment data;
  data.tests.push_back(measure(m, s, field_points(3, 3, 20) * 1.5));
  fem::ResponseSurface law = fem::ResponseSurface::preset("paper14", 0.05);
  Eigen::VectorXd J = Eigen::VectorXd::Zero(14);
  J(0) = 0.25, J(8) = 0.06, J(6) = 0.01, J(12) = 0.01;
  law.set_coefficients(J);
  std::vector<Parameter> p;
  for (const std::string& name : law.coefficient_names()) p.push_back(Parameter{name});
  ObjectiveOptions o;
  o.sensitivities_after = true;
  EXPECT_FALSE(Objective({m}, data, law, p, o).keeps_simulations());
}

// The most stretched tests run first (Objective::order): wale-30 (pull and held strain 0.3), then
// course-20 (0.3 and 0.2), then the two without a held strain in the experiment's order.
TEST(Objective, RunsTheMostStretchedTestsFirst) {
  const RigCampaign c = rig_campaign();
  const Objective objective(c.models, c.data, c.law, c.parameters);
  EXPECT_EQ(objective.order(), (std::vector<int>{1, 3, 0, 2}));
}

// A failed test fails the evaluation; the later tests are cancelled, and the message names the first
// failed test on any number of threads.
TEST(Objective, AFailedTestNamesTheFirstFailureOnAnyNumberOfThreads) {
  const RigCampaign c = rig_campaign();
  Eigen::VectorXd J = c.law.coefficients();
  J(8) = -0.2;  // c1 < 0: the wale softens; the course-pulled test with a held wale strain fails
  std::string serial;
  for (int threads : {1, 2, 4}) {
    ObjectiveOptions o;
    o.threads = threads;
    const Objective objective(c.models, c.data, c.law, c.parameters, o);
    const Evaluation e = objective.evaluate(J, false);
    EXPECT_FALSE(e.ok);
    if (threads == 1) serial = e.message;
    EXPECT_EQ(e.message, serial) << threads << " threads";
  }
  EXPECT_EQ(serial.rfind("test course-20: ", 0), 0u) << serial;
}

// Issue 15: what `mpirun -np N tricot identify` does (src/mpi), in one process: the tests are split
// round-robin over N "ranks", each share evaluated on its own as a rank would, and the objective puts
// the values together. Each test's arithmetic is the same, so the result is the one-process one bit
// for bit, and a failed test on any rank gives the same message.
class InProcessSplit final : public TestSplit {
 public:
  explicit InProcessSplit(int ranks) : ranks_(ranks) {}
  std::vector<TestValues> evaluate(
      const Eigen::VectorXd&, bool, int tests,
      const std::function<std::vector<TestValues>(const std::vector<int>&)>& local) const override {
    std::vector<TestValues> all(tests);
    for (int r = 0; r < ranks_; ++r) {
      std::vector<int> mine;
      for (int t = r; t < tests; t += ranks_) mine.push_back(t);
      std::vector<TestValues> v = local(mine);
      for (int t : mine) all[t] = std::move(v[t]);
    }
    return all;
  }

 private:
  int ranks_;
};

TEST(Objective, TestsSplitOverRanksGiveTheOneProcessResultBitForBit) {
  const RigCampaign c = rig_campaign();
  Eigen::VectorXd J = c.law.coefficients();
  J(0) *= 1.1, J(8) *= 0.9;
  Objective objective(c.models, c.data, c.law, c.parameters);
  const Evaluation one = objective.evaluate(J, true);
  ASSERT_TRUE(one.ok) << one.message;
  for (int ranks : {1, 2, 3, 4, 5}) {
    objective.set_split(std::make_shared<InProcessSplit>(ranks));
    const Evaluation e = objective.evaluate(J, true);
    ASSERT_TRUE(e.ok) << e.message;
    EXPECT_TRUE((e.y.array() == one.y.array()).all()) << ranks << " ranks";
    EXPECT_TRUE((e.r.array() == one.r.array()).all()) << ranks << " ranks";
    EXPECT_TRUE((e.jacobian.array() == one.jacobian.array()).all()) << ranks << " ranks";
  }
}

TEST(Objective, AFailedTestOnAnyRankNamesTheSameFirstFailure) {
  const RigCampaign c = rig_campaign();
  Eigen::VectorXd J = c.law.coefficients();
  J(8) = -0.2;  // as above: course-20 (test 3) fails
  Objective objective(c.models, c.data, c.law, c.parameters);
  const std::string one = objective.evaluate(J, false).message;
  EXPECT_EQ(one.rfind("test course-20: ", 0), 0u) << one;
  for (int ranks : {2, 3, 4}) {
    objective.set_split(std::make_shared<InProcessSplit>(ranks));
    const Evaluation e = objective.evaluate(J, false);
    EXPECT_FALSE(e.ok);
    EXPECT_EQ(e.message, one) << ranks << " ranks";
  }
}

}  // namespace
}  // namespace tricot::ident
