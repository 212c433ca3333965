#include "tricot/fem/corotational.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "testing/fd_check.hpp"
#include "testing/law_eval.hpp"
#include "testing/record.hpp"
#include "testing/states.hpp"
#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::fem;
using tricot::test::JacobianMatches;
using tricot::test::P_of;
using tricot::test::record_scientific;
using tricot::test::rot;
using tricot::test::shear;

namespace {

/// Central differences (h = 1e-6) of these smooth maps are exact to ~1e-9 relative; a wrong term is O(1).
constexpr double kFdTol = 1e-7;
/// Two evaluations of the same closed form through different but exact algebra agree to round-off.
constexpr double kRoundOff = 1e-12;
/// The acceptance bound for the simple-shear closed form.
constexpr double kSimpleShearTol = 1e-6;

/// A knit-like orthotropic membrane [N/mm]: stiff course, soft wale, little shear.
CorotationalOrthotropic knit() { return {0.8, 0.2, 0.1, 0.05}; }

std::vector<test::State> states() {
  Mat2 combined;
  combined << 1.9, 0.6, -0.3, 1.2;
  std::vector<test::State> s = test::orthotropic_law_states({"large stretch", Vec2(2.5, 1.4).asDiagonal()}, combined);
  s.push_back({"simple shear gamma 3", shear(3)});
  return s;
}

}  // namespace

TEST(CorotationalOrthotropic, TangentMatchesFiniteDifferencesFromIdentityToLargeRotations) {
  double worst = 0;
  const CorotationalOrthotropic law = knit();
  for (const Mat2& Q : {Mat2(Mat2::Identity()), rot(30)}) {
    for (const auto& s : states()) {
      LawOutput out;
      law.evaluate({s.F, Q}, {true, false}, out);
      auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return flatten(P_of(law, unflatten(Vec4(x)), Q)); };
      EXPECT_TRUE(JacobianMatches(P, flatten(s.F), out.A, kFdTol)) << s.name;
      worst = std::max(worst, tricot::test::jacobian_error(P, flatten(s.F), out.A));
    }
  }
  record_scientific("max_tangent_fd_rel_error", worst);
}

TEST(CorotationalOrthotropic, CoefficientSensitivitiesAreExactBasisStresses) {
  double worst = 0;
  for (const auto& s : states()) {
    const Mat2 Q = rot(-40);
    CorotationalOrthotropic law = knit();
    LawOutput out;
    law.evaluate({s.F, Q}, {false, true}, out);
    ASSERT_EQ(out.dP_dc.size(), 4u);
    Eigen::MatrixXd J(4, 4);
    for (int k = 0; k < 4; ++k) J.col(k) = flatten(out.dP_dc[k]);
    auto P = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
      CorotationalOrthotropic l = law;
      l.set_coefficients(c);
      return flatten(P_of(l, s.F, Q));
    };
    if (s.name == "identity") {
      EXPECT_LT(J.norm(), kRoundOff);  // no strain, no stress, whatever the coefficients
      continue;
    }
    EXPECT_TRUE(JacobianMatches(P, law.coefficients(), J, kFdTol)) << s.name;
    worst = std::max(worst, tricot::test::jacobian_error(P, law.coefficients(), J));
    // Linear in the coefficients: P = Σ c_k ∂P/∂c_k.
    EXPECT_LT((J * law.coefficients() - flatten(P_of(law, s.F, Q))).norm(), kRoundOff) << s.name;
  }
  record_scientific("max_dP_dc_fd_rel_error", worst);
}

TEST(CorotationalOrthotropic, RigidRotationRotatesPAndLeavesTheLocalStressUnchanged) {
  const CorotationalOrthotropic law = knit();
  Mat2 F;
  F << 1.7, 0.4, -0.2, 1.1;
  const Mat2 Q = rot(25);
  double worst = 0;
  for (double deg : {37.0, 90.0, 180.0, -100.0}) {
    const Mat2 Q0 = rot(deg);
    const double eP = (P_of(law, Q0 * F, Q) - Q0 * P_of(law, F, Q)).norm();
    const double eT = (law.material_frame_stress({Q0 * F, Q}) - law.material_frame_stress({F, Q})).norm();
    EXPECT_LT(eP, kRoundOff) << deg;
    EXPECT_LT(eT, kRoundOff) << deg;
    worst = std::max({worst, eP / P_of(law, F, Q).norm(), eT / law.material_frame_stress({F, Q}).norm()});
  }
  record_scientific("rotation_max_rel_error", worst);
  // A rigid rotation alone gives no stress.
  EXPECT_LT(P_of(law, rot(140), Q).norm(), kRoundOff);
}

TEST(CorotationalOrthotropic, NinetyDegreeMaterialAngleSwapsCourseAndWale) {
  const CorotationalOrthotropic law = knit();
  const CorotationalOrthotropic swapped(0.2, 0.8, 0.1, 0.05);
  double worst = 0;
  for (const auto& s : states()) {
    const double e = (P_of(law, s.F, rot(90)) - P_of(swapped, s.F, Mat2::Identity())).norm();
    EXPECT_LT(e, kRoundOff) << s.name;
    if (s.name != "identity") worst = std::max(worst, e / P_of(swapped, s.F, Mat2::Identity()).norm());
  }
  record_scientific("swap_max_rel_error", worst);
}

TEST(CorotationalOrthotropic, SimpleShearReproducesTheLogRateClosedFormUpToGammaTen) {
  const double G = 0.3;
  const CorotationalOrthotropic law = CorotationalOrthotropic::isotropic(G, 1.7);
  double max_err = 0;
  for (int i = 0; i <= 1000; ++i) {
    const double gamma = 0.01 * i;
    const Mat2 sigma = Law::cauchy(shear(gamma), P_of(law, shear(gamma), Mat2::Identity()));
    const SimpleShearStress ref = simple_shear_log_rate(G, gamma);
    const double scale = std::max(std::abs(ref.s12), 1e-300);
    max_err = std::max({max_err, std::abs(sigma(0, 1) - ref.s12) / scale, std::abs(sigma(1, 0) - ref.s12) / scale});
    if (gamma > 0) {
      max_err = std::max({max_err, std::abs(sigma(0, 0) - ref.s11) / std::abs(ref.s11),
                          std::abs(sigma(1, 1) - ref.s22) / std::abs(ref.s22)});
    } else {
      EXPECT_EQ(sigma.norm(), 0.0);
    }
  }
  record_scientific("simple_shear_max_rel_error", max_err);
  EXPECT_LE(max_err, kSimpleShearTol);
}

TEST(CorotationalOrthotropic, FlattenedElementCarriesVanishingShear) {
  const double G = 1.0;
  const CorotationalOrthotropic law = CorotationalOrthotropic::isotropic(G, 3.0);
  double previous = 1e300;
  for (double gamma : {5.0, 10.0, 100.0, 1000.0}) {
    const double s12 = Law::cauchy(shear(gamma), P_of(law, shear(gamma), Mat2::Identity()))(0, 1);
    EXPECT_NEAR(s12, simple_shear_log_rate(G, gamma).s12, kSimpleShearTol * s12) << gamma;
    EXPECT_LT(s12, previous) << gamma;
    previous = s12;
  }
  EXPECT_LT(previous, 0.03 * G);  // 4 asinh(500)/√(4 + 10⁶) = 0.0276 at γ = 1000
}

TEST(SimpleShearClosedForms, AllRatesAgreeWithLinearElasticityAtSmallShear) {
  const double G = 2.0, gamma = 1e-4;
  for (const auto& s :
       {simple_shear_log_rate(G, gamma), simple_shear_jaumann(G, gamma), simple_shear_green_naghdi(G, gamma)}) {
    EXPECT_NEAR(s.s12, G * gamma, 1e-6 * G * gamma);
    EXPECT_NEAR(s.s11, G * gamma * gamma / 2, 1e-4 * G * gamma * gamma);
    EXPECT_EQ(s.s22, -s.s11);
  }
}

TEST(SimpleShearClosedForms, GreenNaghdiIsFiniteThroughBetaPiOverFourAndDiffersFromTheOthers) {
  // γ = 2 ⇒ β = π/4: σ12 = −4G ln cos(π/4) = 2G ln 2, σ11 = 4G(π/4 − 1/2).
  const SimpleShearStress gn = simple_shear_green_naghdi(1.0, 2.0);
  EXPECT_NEAR(gn.s12, 2 * std::log(2.0), kRoundOff);
  EXPECT_NEAR(gn.s11, std::numbers::pi - 2, kRoundOff);
  EXPECT_NEAR(simple_shear_jaumann(1.0, 2.0).s12, std::sin(2.0), kRoundOff);
  EXPECT_NEAR(simple_shear_log_rate(1.0, 2.0).s12, 4 * std::asinh(1.0) / std::sqrt(8.0), kRoundOff);
}

TEST(CorotationalOrthotropic, PlaneStressIsotropicMatchesEngineeringModuliAndThickness) {
  const double E = 2.0, nu = 0.3, eps = 1e-7;
  const CorotationalOrthotropic law = CorotationalOrthotropic::isotropic_plane_stress(E, nu);
  // Uniaxial stress: F = diag(1 + ε, 1 − ν ε) gives P11 = E ε, P22 = 0 to first order.
  LawOutput out;
  law.evaluate({Vec2(1 + eps, 1 - nu * eps).asDiagonal(), Mat2::Identity()}, {false, false}, out);
  EXPECT_NEAR(out.P(0, 0), E * eps, 1e-6 * E * eps);
  EXPECT_NEAR(out.P(1, 1), 0.0, 1e-6 * E * eps);
  // 3-D Hencky law in plane stress: ln λ3 = −ν/(1 − ν) (ln λ1 + ln λ2), exactly.
  const Mat2 F = Vec2(1.5, 1.2).asDiagonal();
  law.evaluate({rot(33) * F, rot(10)}, {false, false}, out);
  EXPECT_NEAR(std::log(out.lambda3), -nu / (1 - nu) * std::log(1.5 * 1.2), kRoundOff);
}

TEST(CorotationalOrthotropic, IsotropicGKMapsToTheReducedStiffness) {
  EXPECT_EQ(CorotationalOrthotropic::isotropic(0.5, 2.0).coefficients(), Eigen::Vector4d(2.5, 2.5, 1.5, 0.5));
}

TEST(CorotationalOrthotropic, RejectsAStiffnessThatIsNotPositiveDefinite) {
  EXPECT_THROW(CorotationalOrthotropic(1.0, 1.0, 1.0, 0.1), InputError);
  EXPECT_THROW(CorotationalOrthotropic(-1.0, 1.0, 0.0, 0.1), InputError);
  EXPECT_THROW(CorotationalOrthotropic(1.0, 1.0, 0.0, 0.0), InputError);
  EXPECT_THROW(CorotationalOrthotropic::isotropic_plane_stress(1.0, 1.0), InputError);
  CorotationalOrthotropic law = knit();
  EXPECT_THROW(law.set_coefficients(Eigen::Vector3d(1, 1, 1)), InputError);
}

TEST(CorotationalOrthotropic, InvertedElementGivesNaN) {
  LawOutput out;
  knit().evaluate({Vec2(-1.0, 1.0).asDiagonal(), Mat2::Identity()}, {true, true}, out);
  EXPECT_TRUE(std::isnan(out.P(0, 0)));
  EXPECT_TRUE(std::isnan(out.A(0, 0)));
}
