#include "tricot/ident/identifiability.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <vector>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::ident;

namespace {
/// Small dense eigen/LDLT solves of O(1) matrices: round-off.
constexpr double kRoundOff = 1e-10;
}  // namespace

// Two tests of a linear model in J = (2, 4): test A sees J1 + J2 only, test B sees J1 − J2 weakly.
// In relative units (D = diag(2, 4)) the information matrix is closed form.
TEST(Identifiability, ReportsPinnedCoefficientsWeakDirectionAndEachTestsShare) {
  Eigen::MatrixXd S(3, 2);
  S << 1, 1,        // test A
      1, 1,         // test A
      0.01, -0.01;  // test B
  const Eigen::Vector2d J(2, 4), scale(1, 1);
  const IdentifiabilityReport r = identifiability(S, J, scale, {{0, 1}, {2}});
  // A = S D: rows (2, 4), (2, 4), (0.02, −0.04); M = AᵀA.
  Eigen::MatrixXd A = S * Eigen::Vector2d(2, 4).asDiagonal();
  const Eigen::MatrixXd M = A.transpose() * A;
  const Eigen::MatrixXd Minv = M.inverse();
  EXPECT_NEAR(r.relative_std_error(0), std::sqrt(Minv(0, 0)), kRoundOff * std::sqrt(Minv(0, 0)));
  EXPECT_NEAR(r.relative_std_error(1), std::sqrt(Minv(1, 1)), kRoundOff * std::sqrt(Minv(1, 1)));
  EXPECT_FALSE(r.pinned[0]);  // only the weak test B separates them: σ ≈ 10 relative
  EXPECT_FALSE(r.pinned[1]);
  // The weak direction is (nearly) the one test A cannot see: A's row ⟂ v, i.e. v ∝ (4, −2)/√20.
  EXPECT_NEAR(std::abs(r.least_identifiable.dot(Eigen::Vector2d(2, 4).normalized())), 0.0, 1e-3);
  EXPECT_NEAR(r.trace_share[0] + r.trace_share[1], 1.0, kRoundOff);
  EXPECT_NEAR(r.trace_share[0], 40.0 / (40.0 + 0.0004 + 0.0016), kRoundOff);
  EXPECT_NEAR(r.weak_direction_share[0] + r.weak_direction_share[1], 1.0, kRoundOff);
  EXPECT_GT(r.weak_direction_share[1], 0.5);  // test B carries most of what is known along v
}

TEST(Identifiability, AColumnTheDataCannotSeeHasAnInfiniteErrorAndIsTheWeakDirection) {
  Eigen::MatrixXd S(2, 2);
  S << 1, 0, 2, 0;
  const IdentifiabilityReport r = identifiability(S, Eigen::Vector2d(1, 1), Eigen::Vector2d(1, 1), {{0, 1}});
  EXPECT_TRUE(r.pinned[0] == (r.relative_std_error(0) < 0.1));
  EXPECT_TRUE(std::isinf(r.relative_std_error(1)));
  EXPECT_NEAR(r.least_identifiable(1), 1.0, kRoundOff);
}

// The candidate that measures the unseen direction wins under both criteria; a redundant one
// leaves the worst standard error infinite.
TEST(TestDesign, PrefersTheCandidateThatSeesTheUnidentifiedDirection) {
  Eigen::MatrixXd S(2, 2);
  S << 1, 0, 0, 0.01;  // J2 barely seen
  const Eigen::Vector2d J(1, 1), scale(1, 1);
  std::vector<DesignCandidate> c(2);
  c[0].name = "more of J1";
  c[0].S = Eigen::MatrixXd(1, 2);
  c[0].S << 1, 0;
  c[1].name = "J2";
  c[1].S = Eigen::MatrixXd(1, 2);
  c[1].S << 0, 1;
  for (DesignCriterion k : {DesignCriterion::d_optimal, DesignCriterion::a_optimal}) {
    const DesignSuggestion s = suggest_test(S, J, scale, c, k);
    EXPECT_EQ(s.best, 1) << to_string(k);
    EXPECT_NEAR(s.worst_std_error_now, 100.0, 1e-8);
    // With J2 measured: M = diag(1, 1 + 1e-4), worst σ = 1/√1 = 1.
    EXPECT_NEAR(s.worst_std_error_with[1], 1.0, 1e-8);
    EXPECT_NEAR(s.worst_std_error_with[0], 100.0, 1e-8);
  }
  const DesignSuggestion d = suggest_test(S, J, scale, c, DesignCriterion::d_optimal);
  EXPECT_NEAR(d.score[1], std::log(1.0 * (1e-4 + 1)), 1e-9);  // log det diag(1, 1.0001)
  EXPECT_NEAR(d.score[0], std::log(2.0 * 1e-4), 1e-9);
  EXPECT_THROW(suggest_test(S, J, scale, {}, DesignCriterion::a_optimal), InputError);
}
