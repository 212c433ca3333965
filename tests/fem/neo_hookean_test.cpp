#include "tricot/fem/neo_hookean.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <sstream>

#include "testing/fd_check.hpp"
#include "testing/law_eval.hpp"
#include "testing/record.hpp"
#include "testing/states.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

using test::eval;
using test::record;
using test::rotation;

// Central differences (h = 1e-6) of a smooth law whose λ3 is solved to machine precision.
constexpr double kTangentTol = 1e-7;
// Closed-form uniaxial/equibiaxial stresses computed from the same λ3 equation.
constexpr double kClosedFormTol = 1e-10;

std::vector<test::State> states() {
  Mat2 compressed;
  compressed << 0.6, 0.1, 0.0, 0.8;
  std::vector<test::State> s = test::isotropic_law_states(Mat2(Eigen::Vector2d(3.0, 0.6).asDiagonal()));
  s.push_back({"compression", compressed});
  return s;
}

/// σ33 = 0 in closed form for a given in-plane J2 = det C₂: μ(t − 1) + λ/2 ln(J2 t) = 0, by bisection
/// (independent of the law's Newton).
double out_of_plane_C33(double mu, double lam, double J2) {
  double lo = 1e-6, hi = 1e6;
  for (int it = 0; it < 200; ++it) {
    const double t = std::sqrt(lo * hi);
    (mu * (t - 1) + 0.5 * lam * std::log(J2 * t) > 0 ? hi : lo) = t;
  }
  return std::sqrt(lo * hi);
}

TEST(NeoHookean, RejectsNonPositiveShearModulus) {
  EXPECT_THROW(NeoHookean(0.0, 1.0), InputError);
  EXPECT_THROW(NeoHookean(1.0, -1.0), InputError);
  NeoHookean law(1, 1);
  EXPECT_THROW(law.set_coefficients(Eigen::Vector3d(1, 1, 1)), InputError);
  EXPECT_FALSE(law.linear_in_coefficients());
}

TEST(NeoHookean, TangentMatchesFiniteDifferencesOfTheStress) {
  for (double lam : {0.0, 0.8, 50.0}) {
    const NeoHookean law(0.4, lam);
    for (const auto& [what, F] : states()) {
      auto P_of_F = [&](const Eigen::VectorXd& f) -> Eigen::VectorXd { return flatten(eval(law, unflatten(f)).P); };
      EXPECT_TRUE(test::JacobianMatches(P_of_F, flatten(F), eval(law, F).A, kTangentTol)) << what << " λ=" << lam;
      std::ostringstream key;
      key << what << " lambda=" << lam;
      record(key.str(), test::jacobian_error(P_of_F, flatten(F), eval(law, F).A));
    }
  }
}

TEST(NeoHookean, CoefficientDerivativesMatchFiniteDifferences) {
  const Eigen::Vector2d c0(0.4, 0.9);
  NeoHookean law(c0(0), c0(1));
  for (const auto& [what, F] : states()) {
    if (what == "identity") continue;  // P ≡ 0 there
    const LawOutput out = eval(law, F, true);
    ASSERT_EQ(out.dP_dc.size(), 2u);
    Eigen::MatrixXd J(4, 2);
    for (int k = 0; k < 2; ++k)  // entry-wise: GCC 12 misreads a Vec4 column copy
      for (int r = 0; r < 4; ++r) J(r, k) = out.dP_dc[k](r / 2, r % 2);
    auto P_of_c = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
      NeoHookean l = law;
      l.set_coefficients(c);
      return flatten(eval(l, F).P);
    };
    EXPECT_TRUE(test::JacobianMatches(P_of_c, c0, J, kTangentTol)) << what;
  }
}

TEST(NeoHookean, PlaneStressOutOfPlaneStretchSatisfiesSigma33Zero) {
  const double mu = 0.4, lam = 0.9;
  const NeoHookean law(mu, lam);
  for (const auto& [what, F] : states()) {
    const double J2 = std::pow(F.determinant(), 2);
    EXPECT_NEAR(std::pow(eval(law, F).lambda3, 2), out_of_plane_C33(mu, lam, J2), 1e-12) << what;
  }
}

TEST(NeoHookean, EquibiaxialAndUniaxialStressesMatchTheClosedForm) {
  const double mu = 0.4, lam = 0.9;
  const NeoHookean law(mu, lam);
  for (int n = 0; n <= 100; ++n) {
    const double l = 1.01 + 1.99 * n / 100;
    // Equibiaxial: P11 = μ (λ − t/λ), t from σ33 = 0 with J2 = λ⁴.
    const double t = out_of_plane_C33(mu, lam, std::pow(l, 4));
    const Mat2 Fe = Mat2(Eigen::Vector2d(l, l).asDiagonal());
    const double Pe = mu * (l - t / l);
    EXPECT_NEAR(eval(law, Fe).P(0, 0), Pe, kClosedFormTol * std::abs(Pe));
    // Uniaxial: P22 = 0 ⇔ λ2² = t, so P11 = μ (λ − t/λ) with t from J2 = λ² t.
    double lo = 1e-6, hi = 1e6;  // solve t = out_of_plane_C33(λ² t) by bisection on log t
    for (int it = 0; it < 200; ++it) {
      const double s = std::sqrt(lo * hi);
      (out_of_plane_C33(mu, lam, l * l * s) > s ? lo : hi) = s;
    }
    const double tu = std::sqrt(lo * hi);
    const Mat2 Fu = Mat2(Eigen::Vector2d(l, std::sqrt(tu)).asDiagonal());
    const LawOutput out = eval(law, Fu);
    EXPECT_NEAR(out.P(1, 1), 0, 1e-12);
    EXPECT_NEAR(out.P(0, 0), mu * (l - tu / l), kClosedFormTol * mu * l);
  }
}

TEST(NeoHookean, SmallStrainModulusIsYoungs) {
  const double mu = 0.4, lam = 0.9;
  const NeoHookean law(mu, lam);
  const Mat4 A = eval(law, Mat2::Identity()).A;
  const double E = A(0, 0) - A(0, 3) * A(3, 0) / A(3, 3);  // condensed on P22 = 0
  EXPECT_NEAR(E, mu * (3 * lam + 2 * mu) / (lam + mu), 1e-14);
}

TEST(NeoHookean, StressRotatesWithTheBody) {
  const NeoHookean law(0.4, 0.9);
  for (const auto& [what, F] : states())
    for (double a : {0.3, 1.9, -2.5}) {
      const Mat2 Q = rotation(a);
      const Mat2 P = eval(law, F).P;
      EXPECT_LT((eval(law, Q * F).P - Q * P).norm(), 1e-13 * std::max(1.0, P.norm())) << what;
    }
}

TEST(NeoHookean, InvertedDeformationGivesNaN) {
  const NeoHookean law(0.4, 0.9);
  EXPECT_TRUE(std::isnan(eval(law, Mat2(Eigen::Vector2d(1, -1).asDiagonal())).P(0, 0)));
}

}  // namespace
}  // namespace tricot::fem

namespace tricot::fem {
namespace {

// (E, ν) as the coefficients: the same stress as (μ, λ) = (E/(2(1 + ν)), Eν/((1 + ν)(1 − 2ν))), and
// ∂P/∂(E, ν) by the chain rule vs central differences, in plane stress and plane strain.
TEST(NeoHookean, YoungsModulusAndPoissonsRatioAreTheSameLawWithTheirOwnDerivatives) {
  const double E = 0.9, nu = 0.35, mu = E / (2 * (1 + nu)), lam = E * nu / ((1 + nu) * (1 - 2 * nu));
  for (Kinematics k : {Kinematics::plane_stress, Kinematics::plane_strain}) {
    const NeoHookean law(YoungPoisson{E, nu}, k);
    EXPECT_EQ(law.coefficient_names(), (std::vector<std::string>{"E", "nu"}));
    EXPECT_FALSE(law.linear_in_coefficients());
    const NeoHookean lame(mu, lam, k);
    for (const auto& [what, F] : states()) {
      EXPECT_LT((eval(law, F).P - eval(lame, F).P).cwiseAbs().maxCoeff(), 1e-14) << what;
      if (what == "identity") continue;
      const LawOutput out = eval(law, F, true);
      Eigen::MatrixXd J(4, 2);
      for (int c = 0; c < 2; ++c)
        for (int r = 0; r < 4; ++r) J(r, c) = out.dP_dc[static_cast<size_t>(c)](r / 2, r % 2);
      auto P_of_c = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
        NeoHookean l = law;
        l.set_coefficients(c);
        return flatten(eval(l, F).P);
      };
      EXPECT_TRUE(test::JacobianMatches(P_of_c, Eigen::Vector2d(E, nu), J, kTangentTol)) << what << " " << to_string(k);
    }
  }
  EXPECT_THROW(NeoHookean(YoungPoisson{0.0, 0.3}), InputError);
  EXPECT_THROW(NeoHookean(YoungPoisson{1.0, 0.5}), InputError);
}

}  // namespace
}  // namespace tricot::fem
