// The compressible Mooney–Rivlin membrane (docs/theory.md §5.2): P from an energy written here
// independently, tangent and ∂P/∂c vs central differences in plane stress and plane strain, σ33 = 0,
// and the small-strain moduli from μ = 2 (C10 + C01) and κ.
#include "tricot/fem/compressible_mooney_rivlin.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "testing/fd_check.hpp"
#include "testing/law_eval.hpp"
#include "testing/record.hpp"
#include "testing/states.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

using test::eval;

constexpr double kTangentTol = 1e-7;  // central differences, h = 1e-6
constexpr double kEnergyTol = 1e-7;   // P vs central differences of the energy
constexpr double kModulusTol = 1e-12;

const std::vector<MooneyRivlinTerm> kTerms = {{1, 0, 0.3}, {0, 1, 0.05}, {2, 0, 0.02}, {1, 1, 0.01}};
constexpr double kKappa = 2.0;

// W(F, C33) from the 3-D invariants, written out: Σ C_ij (Ī1 − 3)^i (Ī2 − 3)^j + κ/2 (ln J)².
double energy(const Mat2& F, double t) {
  const Mat2 C = F.transpose() * F;
  const double I1 = C.trace() + t, I2 = C.determinant() + t * C.trace(), I3 = t * C.determinant();
  const double x1 = I1 / std::cbrt(I3) - 3, x2 = I2 / std::pow(I3, 2.0 / 3) - 3;
  double W = 0.5 * kKappa * std::pow(0.5 * std::log(I3), 2);
  for (const auto& m : kTerms) W += m.C * std::pow(x1, m.i) * std::pow(x2, m.j);
  return W;
}

std::vector<test::State> states() {
  Mat2 sheared;
  sheared << 1.3, 0.4, -0.1, 0.9;
  std::vector<test::State> s = test::isotropic_law_states(Mat2(Eigen::Vector2d(1.8, 0.7).asDiagonal()));
  s.push_back({"sheared", sheared});
  return s;
}

TEST(CompressibleMooneyRivlin, StressIsTheEnergysDerivativeAndPlaneStressHasSigma33Zero) {
  for (Kinematics k : {Kinematics::plane_stress, Kinematics::plane_strain}) {
    const CompressibleMooneyRivlin law(kTerms, kKappa, k);
    for (const auto& [what, F] : states()) {
      const LawOutput out = eval(law, F);
      const double t = out.lambda3 * out.lambda3;
      if (k == Kinematics::plane_strain) {
        EXPECT_EQ(t, 1.0);
      }
      const double h = 1e-6;
      if (k == Kinematics::plane_stress) {  // ∂W/∂C33 = 0 at the law's C33
        EXPECT_NEAR((energy(F, t + h) - energy(F, t - h)) / (2 * h), 0, kEnergyTol) << what;
      }
      Mat2 dW;  // at fixed C33, the envelope of the condition above
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          Mat2 e = Mat2::Zero();
          e(i, j) = h;
          dW(i, j) = (energy(F + e, t) - energy(F - e, t)) / (2 * h);
        }
      EXPECT_LT((out.P - dW).cwiseAbs().maxCoeff(), kEnergyTol) << what << " " << to_string(k);
    }
  }
}

TEST(CompressibleMooneyRivlin, TangentAndCoefficientDerivativesMatchFiniteDifferences) {
  for (Kinematics k : {Kinematics::plane_stress, Kinematics::plane_strain}) {
    const CompressibleMooneyRivlin law(kTerms, kKappa, k);
    const Eigen::VectorXd c0 = law.coefficients();
    for (const auto& [what, F] : states()) {
      auto P_of_F = [&](const Eigen::VectorXd& f) -> Eigen::VectorXd { return flatten(eval(law, unflatten(f)).P); };
      EXPECT_TRUE(test::JacobianMatches(P_of_F, flatten(F), eval(law, F).A, kTangentTol))
          << what << " " << to_string(k);
      test::record(std::string("tangent ") + what + " " + to_string(k),
                   test::jacobian_error(P_of_F, flatten(F), eval(law, F).A));
      const LawOutput out = eval(law, F, true);
      ASSERT_EQ(out.dP_dc.size(), kTerms.size() + 1);
      Eigen::MatrixXd J(4, c0.size());
      for (Eigen::Index m = 0; m < c0.size(); ++m)
        for (int r = 0; r < 4; ++r) J(r, m) = out.dP_dc[m](r / 2, r % 2);
      auto P_of_c = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
        CompressibleMooneyRivlin l = law;
        l.set_coefficients(c);
        return flatten(eval(l, F).P);
      };
      if (what != "identity") {
        EXPECT_TRUE(test::JacobianMatches(P_of_c, c0, J, kTangentTol)) << what << " " << to_string(k);
      }
    }
  }
}

// At F = I: no stress, and the tangent of linear elasticity with μ = 2 (C10 + C01), K = κ: plane strain
// A1111 = K + 4μ/3, A1122 = K − 2μ/3, A1212 = μ; plane stress E/(1 − ν²) and νE/(1 − ν²).
TEST(CompressibleMooneyRivlin, SmallStrainModuliAreThoseOfMuAndKappa) {
  const double mu = 2 * (0.3 + 0.05), K = kKappa;
  const LawOutput strain = eval(CompressibleMooneyRivlin(kTerms, K, Kinematics::plane_strain), Mat2::Identity());
  EXPECT_LT(strain.P.cwiseAbs().maxCoeff(), kModulusTol);
  EXPECT_NEAR(strain.A(0, 0), K + 4 * mu / 3, kModulusTol);
  EXPECT_NEAR(strain.A(0, 3), K - 2 * mu / 3, kModulusTol);
  EXPECT_NEAR(strain.A(1, 1), mu, kModulusTol);
  const LawOutput stress = eval(CompressibleMooneyRivlin(kTerms, K, Kinematics::plane_stress), Mat2::Identity());
  const double E = 9 * K * mu / (3 * K + mu), nu = (3 * K - 2 * mu) / (2 * (3 * K + mu));
  EXPECT_NEAR(stress.lambda3, 1, kModulusTol);
  EXPECT_NEAR(stress.A(0, 0), E / (1 - nu * nu), kModulusTol);
  EXPECT_NEAR(stress.A(0, 3), nu * E / (1 - nu * nu), kModulusTol);
}

TEST(CompressibleMooneyRivlin, BadCoefficientsAreNamedAndAnInvertedStateIsNaN) {
  EXPECT_THROW(CompressibleMooneyRivlin(kTerms, 0.0), InputError);
  EXPECT_THROW(CompressibleMooneyRivlin({{0, 0, 1.0}}, 1.0), InputError);
  const CompressibleMooneyRivlin law(kTerms, kKappa);
  EXPECT_EQ(law.coefficient_names(), (std::vector<std::string>{"C10", "C01", "C20", "C11", "kappa"}));
  EXPECT_FALSE(law.linear_in_coefficients());
  EXPECT_TRUE(std::isnan(eval(law, Mat2(Eigen::Vector2d(1.0, -1.0).asDiagonal())).P(0, 0)));
}

}  // namespace
}  // namespace tricot::fem
