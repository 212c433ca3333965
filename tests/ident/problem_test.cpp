#include "tricot/ident/problem.hpp"

#include <gtest/gtest.h>

#include "analytic.hpp"
#include "testing/fd_check.hpp"
#include "tricot/core/error.hpp"

namespace tricot::ident {
namespace {

const Eigen::Vector3d kTruth(2.0, 0.7, 0.3);
const Eigen::Vector3d kAt(1.6, 0.9, 0.25);
// Central differences of a smooth function with h = 1e-6: truncation ~h², round-off ~1e-16/h.
constexpr double kCentralAgreement = 1e-8;
// Forward differences: truncation ~h · |f''|/|f'|.
constexpr double kForwardAgreement = 1e-5;

TEST(Problem, ExactJacobianOfTheScaledResidualsMatchesFiniteDifferences) {
  const auto p = test::curve_fit(kTruth, kAt);
  const Evaluation e = p.evaluate(kAt, true);
  ASSERT_TRUE(e.ok);
  auto r = [&](const Eigen::VectorXd& J) { return p.evaluate(J, false).r; };
  EXPECT_TRUE(tricot::test::JacobianMatches(r, kAt, e.jacobian, kCentralAgreement));
}

TEST(Problem, FiniteDifferenceJacobiansAgreeWithTheExactOne) {
  const auto p = test::curve_fit(kTruth, kAt);
  const Evaluation exact = evaluate(p, kAt, true, {});
  for (auto [d, tol] :
       {std::pair{Difference::central, kCentralAgreement}, std::pair{Difference::forward, kForwardAgreement}}) {
    JacobianOptions o;
    o.mode = JacobianMode::finite_difference;
    o.difference = d;
    o.threads = 2;
    const Evaluation fd = evaluate(p, kAt, true, o);
    ASSERT_TRUE(fd.ok);
    EXPECT_EQ(fd.evaluations, d == Difference::central ? 7 : 4);
    EXPECT_LT((fd.jacobian - exact.jacobian).cwiseAbs().maxCoeff() / exact.jacobian.cwiseAbs().maxCoeff(), tol)
        << to_string(d);
    // The same residuals to round-off (not bit for bit: see Identify.ResumedFromACheckpoint…).
    EXPECT_LT((fd.r - exact.r).cwiseAbs().maxCoeff(), 1e-14 * exact.r.cwiseAbs().maxCoeff()) << to_string(d);
  }
}

TEST(Problem, ForwardDifferencesStepBackwardWhereTheForwardTrialFails) {
  auto p = test::curve_fit(kTruth, kAt);
  p.fails = [](const Eigen::VectorXd& J) { return J(1) > 0.9; };  // just beyond kAt along tau
  JacobianOptions o;
  o.mode = JacobianMode::finite_difference;
  const Evaluation fd = evaluate(p, kAt, true, o);
  ASSERT_TRUE(fd.ok) << fd.message;
  const Evaluation exact = evaluate(p, kAt, true, {});
  EXPECT_LT((fd.jacobian - exact.jacobian).cwiseAbs().maxCoeff() / exact.jacobian.cwiseAbs().maxCoeff(),
            kForwardAgreement);
}

TEST(Problem, ReusesAGivenBaseEvaluationForForwardDifferences) {
  const auto p = test::curve_fit(kTruth, kAt);
  const Evaluation base = p.evaluate(kAt, false);
  JacobianOptions o;
  o.mode = JacobianMode::finite_difference;
  const Evaluation fd = evaluate(p, kAt, true, o, &base);
  EXPECT_EQ(fd.evaluations, 3);
}

TEST(Parameters, AZeroStartWithoutAScaleIsRejectedByName) {
  try {
    validate({Parameter{"C10", 0.1}, Parameter{"C03", 0.0}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "parameters.C03.scale");
    EXPECT_NE(std::string(e.what()).find("zero start"), std::string::npos);
  }
  EXPECT_NO_THROW(validate({Parameter{"C03", 0.0, 0.01}}));
}

TEST(Parameters, RejectsStartsOutsideBoundsAndRepeatedNames) {
  Parameter p{"C10", 2.0};
  p.upper = 1;
  EXPECT_THROW(validate({p}), InputError);
  EXPECT_THROW(validate({Parameter{"a", 1.0}, Parameter{"a", 2.0}}), InputError);
  EXPECT_THROW(validate({Parameter{"a", NAN}}), InputError);
  EXPECT_THROW(validate({}), InputError);
}

TEST(Parameters, ResolvedScaleIsTheStartMagnitudeUnlessGiven) {
  EXPECT_EQ((Parameter{"a", -3.0}.resolved_scale()), 3.0);
  EXPECT_EQ((Parameter{"a", -3.0, 0.5}.resolved_scale()), 0.5);
}

}  // namespace
}  // namespace tricot::ident
