#include "tricot/ident/groups.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tricot/core/error.hpp"

namespace tricot::ident {
namespace {

TEST(ScaledResiduals, ScalesEachGroupByItsRmsAndWeightAsEquationOne) {
  ScaledResiduals d;
  const Eigen::Vector2d a(3, 4);           // RMS = √12.5
  const Eigen::Vector3d b(0.1, 0.2, 0.2);  // RMS = 0.1732…
  d.add("a", GroupKind::edge_force, 0, a, 2.0);
  d.add("b", GroupKind::field_u, 0, b, 1.0);
  ASSERT_EQ(d.size(), 5);
  EXPECT_EQ(d.groups()[1].offset, 2);
  Eigen::VectorXd y(5);
  y << 3.3, 4, 0.1, 0.25, 0.2;
  const Eigen::VectorXd r = d.residuals(y);
  // f = ½ Σ_g w_g/N_g Σ ((y − y_exp)/s_g)².
  const double sa2 = 12.5, sb2 = (0.01 + 0.04 + 0.04) / 3;
  const double f = 0.5 * (2.0 / 2 * (0.09 / sa2) + 1.0 / 3 * (0.0025 / sb2));
  EXPECT_NEAR(0.5 * r.squaredNorm(), f, 1e-15);
  EXPECT_TRUE(d.sigma_variance().size() == 0);  // RMS scales are not σ
}

// Fixed weights (a published objective's): f = ½ Σ_g w_g Σ_i (y_i − y*_i)², whatever the group's size,
// RMS or σ; a σ per value does not mix with them.
TEST(ScaledResiduals, FixedWeightsAreAbsoluteAndPerValue) {
  ScaledResiduals d(true);
  d.add("a", GroupKind::edge_force, 0, Eigen::Vector2d(3, 4), 2.0, 0.5);  // σ ignored
  d.add("b", GroupKind::field_u, 0, Eigen::Vector3d(0.1, 0.2, 0.2), 100.0);
  Eigen::VectorXd y(5);
  y << 3.3, 4, 0.1, 0.25, 0.2;
  const double f = 0.5 * (2.0 * 0.09 + 100.0 * 0.0025);
  EXPECT_NEAR(0.5 * d.residuals(y).squaredNorm(), f, 1e-15);
  EXPECT_EQ(d.groups()[0].scale, 1.0);
  EXPECT_TRUE(d.sigma_variance().size() == 0);  // no σ: standard errors from the residuals
  EXPECT_THROW(d.add("c", GroupKind::field_v, 0, Eigen::Vector2d(1, 2), 1.0, Eigen::Vector2d(0.1, 0.1)), InputError);
}

TEST(ScaledResiduals, UsesAGivenSigmaAsTheScale) {
  ScaledResiduals d;
  d.add("a", GroupKind::edge_force, 0, Eigen::Vector4d(1, 2, 3, 4), 3.0, 0.5);
  EXPECT_EQ(d.groups()[0].scale, 0.5);
  EXPECT_TRUE(d.groups()[0].sigma);
  const Eigen::VectorXd var = d.sigma_variance();
  ASSERT_EQ(var.size(), 4);
  EXPECT_DOUBLE_EQ(var(0), 3.0 / 4);
  Eigen::MatrixXd dy = Eigen::MatrixXd::Ones(4, 2);
  d.scale_rows(dy);
  EXPECT_DOUBLE_EQ(dy(2, 1), std::sqrt(3.0 / 4) / 0.5);
}

TEST(ScaledResiduals, APerValueSigmaScalesEachRowByItsOwnSigma) {
  ScaledResiduals d;
  const Eigen::Vector3d y_exp(1, 2, 3), sigma(0.1, 0.2, 0.4);
  d.add("f", GroupKind::field_uv, 0, y_exp, 3.0, sigma);
  Eigen::VectorXd y(3);
  y << 1.1, 2.1, 3.1;
  // f = ½ w/N Σ ((y − y_exp)/σ_i)² = ½ · 1 · (1 + 0.25 + 0.0625).
  EXPECT_NEAR(0.5 * d.residuals(y).squaredNorm(), 0.5 * (1 + 0.25 + 0.0625), 1e-12);
  EXPECT_TRUE(d.groups()[0].sigma);
  EXPECT_NEAR(d.groups()[0].scale, std::sqrt((0.01 + 0.04 + 0.16) / 3), 1e-15);  // reported: RMS of σ
  const Eigen::VectorXd var = d.sigma_variance();
  ASSERT_EQ(var.size(), 3);
  EXPECT_NEAR(var(2), 1.0, 1e-15);  // w/N: the covariance is a real one
}

TEST(ScaledResiduals, RowWeightsScaleEachRowsShareOfFAndItsVariance) {
  ScaledResiduals d;
  const Eigen::Vector3d y_exp(1, 2, 3), sigma(0.1, 0.2, 0.4);
  const DataGroup& g = d.add("f", GroupKind::field_uv, 0, y_exp, 3.0, sigma);
  d.weight_rows(g, Eigen::Vector3d(1, 0.25, 0));
  Eigen::VectorXd y(3);
  y << 1.1, 2.1, 3.1;
  // f = ½ w/N Σ ω_i ((y − y_exp)/σ_i)² = ½ (1 · 1 + 0.25 · 0.25 + 0 · 0.0625).
  EXPECT_NEAR(0.5 * d.residuals(y).squaredNorm(), 0.5 * (1 + 0.0625), 1e-12);
  const Eigen::VectorXd var = d.sigma_variance();
  EXPECT_NEAR(var(0), 1.0, 1e-15);  // w ω_i / N
  EXPECT_NEAR(var(1), 0.25, 1e-15);
  EXPECT_EQ(var(2), 0.0);
  EXPECT_THROW(d.weight_rows(d.groups()[0], Eigen::Vector2d(1, 1)), InputError);      // one per row
  EXPECT_THROW(d.weight_rows(d.groups()[0], Eigen::Vector3d(1, -1, 1)), InputError);  // ≥ 0
}

TEST(ScaledResiduals, APerValueSigmaMustBePositiveAndOnePerValue) {
  ScaledResiduals d;
  EXPECT_THROW(
      d.add("f", GroupKind::field_u, 0, Eigen::Vector2d(1, 2), 1.0, Eigen::VectorXd(Eigen::Vector2d(0.1, 0.0))),
      InputError);
  EXPECT_THROW(d.add("f", GroupKind::field_u, 0, Eigen::Vector2d(1, 2), 1.0, Eigen::VectorXd(Eigen::Vector3d(1, 1, 1))),
               InputError);
}

TEST(ScaledResiduals, AllZeroDataWithoutSigmaIsAnError) {
  ScaledResiduals d;
  try {
    d.add("t/field_u", GroupKind::field_u, 0, Eigen::Vector3d::Zero());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "data.t/field_u");
  }
  EXPECT_THROW(d.add("n", GroupKind::field_u, 0, Eigen::Vector2d(1, NAN)), InputError);
  EXPECT_NO_THROW(d.add("z", GroupKind::field_u, 0, Eigen::Vector3d::Zero(), 1, 0.01));
}

TEST(ScaledResiduals, AGroupWhoseRmsOverflowsIsAnErrorNotAZeroWeight) {
  ScaledResiduals d;
  try {
    d.add("t/edge_displacement", GroupKind::edge_displacement, 0, Eigen::Vector3d(1, 2, 1e200));
    FAIL() << "1e200² overflows the sum of squares";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "data.t/edge_displacement");
    EXPECT_NE(std::string(e.what()).find("RMS overflows"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tricot::ident
