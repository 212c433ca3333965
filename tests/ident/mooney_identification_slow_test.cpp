// The paper's §3.3 validation with a heterogeneous field: a clamped strip necks, so data generated
// on a fine mesh differ from any coarser model by its discretisation error, and the identified
// coefficients carry that error amplified by the problem's conditioning (C03 least identifiable).
#include <gtest/gtest.h>

#include <cstdio>

#include "tricot/ident/identify.hpp"
#include "tricot/ident/objective.hpp"
#include "tricot/ident/synthetic.hpp"
#include "uniaxial.hpp"

namespace tricot::ident {
namespace {

// Issue 4 / paper Table 1: C10, C20, C21 within 0.1 %, C03 within 1 %. Measured with these meshes
// (data 24×64 Q8, model 8×20 Q8, start ×0.5): 0.008 %, 0.05 %, 0.04 %, 0.4 %.
constexpr double kTable1 = 1e-3;
constexpr double kTable1C03 = 1e-2;

TEST(MooneyIdentification, ClampedStripRecoversTheTruthFromAFinerMeshFromThreeStarts) {
  const auto truth = fem::paper_mooney_rivlin_terms();
  const fem::TestModel fine = test::uniaxial(24, 64, 10, fem::GripControl::force);
  const fem::TestModel model = test::uniaxial(8, 20, 10, fem::GripControl::force);
  const fem::SimulationResult sim = fem::simulate(fine, fem::MooneyRivlin(truth));
  ASSERT_TRUE(sim.usable()) << sim.message;
  // Points away from the clamp's corner, where the discretisation error concentrates.
  Eigen::Matrix2Xd points = test::field_points(5, 8);
  points.row(1) = (1 + (points.row(1).array() - 1) * 14.0 / 23).matrix();  // y ∈ [1, 15] mm
  Experiment data;
  data.tests.push_back(measure(fine, sim, points));

  for (const Eigen::Vector4d& factor :
       {Eigen::Vector4d(0.5, 0.5, 0.5, 0.5), Eigen::Vector4d(2, 2, 2, 2), Eigen::Vector4d(1.5, 0.7, 0.5, 1.8)}) {
    std::vector<Parameter> params;
    for (int k = 0; k < 4; ++k)
      params.push_back(
          Parameter{"C" + std::to_string(truth[k].i) + std::to_string(truth[k].j), factor(k) * truth[k].C});
    const Objective objective({model}, data, fem::MooneyRivlin(truth), params);
    const IdentifyResult r = identify(objective);
    ASSERT_TRUE(r.converged()) << r.message;
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(r.parameters(k) / truth[k].C, 1.0, kTable1) << params[k].name << " from " << factor.transpose();
    EXPECT_NEAR(r.parameters(3) / truth[3].C, 1.0, kTable1C03) << "C03 from " << factor.transpose();
    std::string errors;
    for (int k = 0; k < 4; ++k) {
      char e[32];
      std::snprintf(e, sizeof e, "%.2e ", r.parameters(k) / truth[k].C - 1);
      errors += e;
    }
    RecordProperty("start_" + std::to_string(factor(0)) + "_" + std::to_string(factor(1)) + "_relative_errors",
                   errors + "iterations " + std::to_string(r.iterations) + " evaluations " +
                       std::to_string(r.evaluations) + " failed " + std::to_string(r.failed_evaluations) +
                       " condition " + std::to_string(r.uncertainty.condition_number) + " least_identifiable_C03 " +
                       std::to_string(r.uncertainty.least_identifiable(3)));
  }
}

TEST(MooneyIdentification, WithHalfAPercentNoiseTheTruthLiesWithinThreeStandardErrors) {
  const auto truth = fem::paper_mooney_rivlin_terms();
  const fem::TestModel fine = test::uniaxial(24, 64, 10, fem::GripControl::force);
  const fem::TestModel model = test::uniaxial(8, 20, 10, fem::GripControl::force);
  const fem::SimulationResult sim = fem::simulate(fine, fem::MooneyRivlin(truth));
  ASSERT_TRUE(sim.usable()) << sim.message;
  Experiment data;
  data.tests.push_back(measure(fine, sim, test::field_points(5, 8)));
  add_noise(data.tests[0], rms_fraction(data.tests[0], 0.005), 42);  // σ recorded: a real covariance

  std::vector<Parameter> params;
  for (const auto& t : truth) params.push_back(Parameter{"C" + std::to_string(t.i) + std::to_string(t.j), 0.5 * t.C});
  const Objective objective({model}, data, fem::MooneyRivlin(truth), params);
  const IdentifyResult r = identify(objective);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_TRUE(r.uncertainty.from_sigma);
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT(std::abs(r.parameters(k) - truth[k].C), 3 * r.uncertainty.std_error(k)) << params[k].name;
    RecordProperty(params[k].name + "_z", std::to_string((r.parameters(k) - truth[k].C) / r.uncertainty.std_error(k)));
  }
  // The weakest coefficient is C03, as the paper found.
  Eigen::Index weakest;
  r.uncertainty.least_identifiable.cwiseAbs().maxCoeff(&weakest);
  EXPECT_EQ(weakest, 3);
}

}  // namespace
}  // namespace tricot::ident
