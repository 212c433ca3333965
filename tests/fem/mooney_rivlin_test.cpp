#include "tricot/fem/mooney_rivlin.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>

#include "testing/fd_check.hpp"
#include "testing/law_eval.hpp"
#include "testing/paths.hpp"
#include "testing/record.hpp"
#include "testing/states.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/neo_hookean.hpp"

namespace tricot::fem {
namespace {

using test::eval;
using test::record;
using test::rotation;

// Central differences with h = 1e-6 on smooth polynomials: truncation ~1e-12, round-off ~1e-10.
constexpr double kTangentTol = 1e-7;
// The closed forms and the law evaluate the same algebra in a different order (issue 2: ≤ 1e-8).
constexpr double kClosedFormTol = 1e-8;
// The lateral stretch of uniaxial tension is found by Newton to machine precision.
constexpr double kNewtonTol = 1e-14;

/// Many (i, j), including cross terms and I2-only terms, to exercise the general form.
std::vector<MooneyRivlinTerm> rich_terms() {
  return {{1, 0, 0.1},   {0, 1, 0.03},  {1, 1, -0.004}, {2, 0, -0.02},
          {0, 2, 0.002}, {2, 1, 0.012}, {0, 3, 0.008},  {3, 0, 0.001}};
}

/// The deformation gradients the tangent is checked at.
std::vector<test::State> states() {
  return test::isotropic_law_states(Mat2(Eigen::Vector2d(3.0, 1 / std::sqrt(3.0)).asDiagonal()));
}

/// F = diag(λ, λ2) with λ2 solved so that P22 = 0 (Newton on the law's own tangent).
Mat2 uniaxial_F(const Law& law, double lambda) {
  Mat2 F = Mat2::Identity();
  F(0, 0) = lambda;
  F(1, 1) = 1.1 / std::sqrt(lambda);
  for (int it = 0; it < 50; ++it) {
    const LawOutput out = eval(law, F);
    const double step = out.P(1, 1) / out.A(3, 3);
    F(1, 1) -= step;
    if (std::abs(step) < kNewtonTol) break;
  }
  return F;
}

/// dP11/dλ along the uniaxial path: the tangent condensed on P22 = 0.
double uniaxial_slope(const Law& law, double lambda) {
  const LawOutput out = eval(law, uniaxial_F(law, lambda));
  return out.A(0, 0) - out.A(0, 3) * out.A(3, 0) / out.A(3, 3);
}

TEST(MooneyRivlin, NamesCoefficientsAfterTheirExponents) {
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  EXPECT_EQ(law.coefficient_names(), (std::vector<std::string>{"C10", "C20", "C21", "C03"}));
  EXPECT_DOUBLE_EQ(law.coefficients()(1), -0.025);
  EXPECT_TRUE(law.linear_in_coefficients());
}

TEST(MooneyRivlin, RejectsBadTerms) {
  EXPECT_THROW(MooneyRivlin({{0, 0, 1.0}}), InputError);
  EXPECT_THROW(MooneyRivlin({{1, 0, 1.0}, {1, 0, 2.0}}), InputError);
  EXPECT_THROW(MooneyRivlin({{-1, 2, 1.0}}), InputError);
  EXPECT_THROW(MooneyRivlin({{1, 0, std::nan("")}}), InputError);
  MooneyRivlin law({{1, 0, 1.0}});
  EXPECT_THROW(law.set_coefficients(Eigen::Vector2d(1, 2)), InputError);
}

TEST(MooneyRivlin, TangentMatchesFiniteDifferencesOfTheStress) {
  for (const auto& terms : {paper_mooney_rivlin_terms(), rich_terms()}) {
    const MooneyRivlin law(terms);
    for (const auto& [what, F] : states()) {
      auto P_of_F = [&](const Eigen::VectorXd& f) -> Eigen::VectorXd { return flatten(eval(law, unflatten(f)).P); };
      EXPECT_TRUE(test::JacobianMatches(P_of_F, flatten(F), eval(law, F).A, kTangentTol)) << what;
      record(terms.size() == 4 ? "paper " + what : "rich " + what,
             test::jacobian_error(P_of_F, flatten(F), eval(law, F).A));
    }
  }
}

TEST(MooneyRivlin, BasisStressesAreTheDerivativesOverTheCoefficients) {
  MooneyRivlin law(rich_terms());
  const Eigen::VectorXd c0 = law.coefficients();
  for (const auto& [what, F] : states()) {
    const LawOutput out = eval(law, F, true);
    ASSERT_EQ(out.dP_dc.size(), static_cast<std::size_t>(c0.size()));
    Eigen::MatrixXd J(4, c0.size());
    for (Eigen::Index k = 0; k < c0.size(); ++k)  // entry-wise: GCC 12 misreads a Vec4 column copy
      for (int r = 0; r < 4; ++r) J(r, k) = out.dP_dc[k](r / 2, r % 2);
    auto P_of_c = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
      MooneyRivlin l = law;
      l.set_coefficients(c);
      return flatten(eval(l, F).P);
    };
    if (what == "identity") {  // P = 0 and every basis stress vanishes at F = I
      EXPECT_LT(J.cwiseAbs().maxCoeff(), 1e-15);
      continue;
    }
    EXPECT_TRUE(test::JacobianMatches(P_of_c, c0, J, kTangentTol)) << what;
    // Linear in c: P = Σ c_k B_k exactly.
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (Eigen::Index k = 0; k < c0.size(); ++k) sum += c0(k) * J.col(k);
    EXPECT_LT((sum - flatten(out.P)).norm(), 1e-13 * std::max(1.0, out.P.norm())) << what;
  }
}

TEST(MooneyRivlin, HomogeneousStatesMatchTheClosedForms) {
  for (const auto& terms : {paper_mooney_rivlin_terms(), rich_terms()}) {
    const MooneyRivlin law(terms);
    double worst[3] = {0, 0, 0};
    for (int n = 0; n <= 200; ++n) {
      const double l = 1.01 + (3.0 - 1.01) * n / 200;
      const Mat2 Fu = uniaxial_F(law, l);
      EXPECT_NEAR(Fu(1, 1), 1 / std::sqrt(l), 1e-12);  // incompressible: λ2 = λ^(−1/2)
      const Mat2 Fe = Mat2(Eigen::Vector2d(l, l).asDiagonal());
      const Mat2 Fs = Mat2(Eigen::Vector2d(l, 1).asDiagonal());
      const HomogeneousMode modes[3] = {HomogeneousMode::uniaxial, HomogeneousMode::equibiaxial,
                                        HomogeneousMode::pure_shear};
      const Mat2 Fs3[3] = {Fu, Fe, Fs};
      for (int m = 0; m < 3; ++m) {
        const LawOutput out = eval(law, Fs3[m]);
        const double exact = mooney_rivlin_nominal_stress(terms, modes[m], l);
        worst[m] = std::max(worst[m], std::abs(out.P(0, 0) - exact) / std::abs(exact));
        EXPECT_NEAR(out.P(0, 1), 0, 1e-15);
        EXPECT_NEAR(out.lambda3 * Fs3[m].determinant(), 1, 1e-15);
      }
      EXPECT_NEAR(eval(law, Fe).P(1, 1), eval(law, Fe).P(0, 0), 1e-12 * std::abs(eval(law, Fe).P(0, 0)));
    }
    const std::string set = terms.size() == 4 ? "paper " : "rich ";
    record(set + "uniaxial", worst[0]);
    record(set + "equibiaxial", worst[1]);
    record(set + "pure shear", worst[2]);
    EXPECT_LE(worst[0], kClosedFormTol) << "uniaxial";
    EXPECT_LE(worst[1], kClosedFormTol) << "equibiaxial";
    EXPECT_LE(worst[2], kClosedFormTol) << "pure shear";
  }
}

TEST(MooneyRivlin, SmallStrainUniaxialModulusIsSixC10LikeAnIncompressibleNeoHookean) {
  const double C10 = 0.37;
  const MooneyRivlin law({{1, 0, C10}});
  EXPECT_NEAR(uniaxial_slope(law, 1.0), 6 * C10, 1e-12);
  // Neo-Hookean with μ = 2 C10 and λ ≫ μ: E = μ(3λ + 2μ)/(λ + μ) → 3μ; O(μ/λ) gap.
  const NeoHookean nh(2 * C10, 2 * C10 * 1e6);
  EXPECT_NEAR(uniaxial_slope(nh, 1.0), 6 * C10, 6 * C10 * 1e-5);
  // The whole small-strain tangent agrees, not just the uniaxial modulus.
  const Mat2 I = Mat2::Identity();
  const Mat4 A_mr = eval(law, I).A, A_nh = eval(nh, I).A;
  // Plane stress of an incompressible solid at F = I: A = μ (δik δjl + δil δjk) + 2μ δij δkl.
  Mat4 A_exact = Mat4::Zero();
  const double mu = 2 * C10;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k)
        for (int l = 0; l < 2; ++l)
          A_exact(2 * i + j, 2 * k + l) =
              mu * ((i == k) * (j == l) + (i == l) * (j == k)) + 2 * mu * (i == j) * (k == l);
  EXPECT_LT((A_mr - A_exact).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((A_nh - A_exact).cwiseAbs().maxCoeff(), 1e-5 * mu);
}

TEST(MooneyRivlin, StressRotatesWithTheBody) {
  const MooneyRivlin law(rich_terms());
  for (const auto& [what, F] : states())
    for (double a : {0.3, 1.9, -2.5}) {
      const Mat2 Q = rotation(a);
      const Mat2 P = eval(law, F).P;
      EXPECT_LT((eval(law, Q * F).P - Q * P).norm(), 1e-13 * std::max(1.0, P.norm())) << what << " " << a;
    }
}

TEST(MooneyRivlin, InvertedDeformationGivesNaN) {
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  Mat2 F;
  F << 1, 0, 0, -0.5;
  EXPECT_TRUE(std::isnan(eval(law, F).P(0, 0)));
}

TEST(MooneyRivlin, PaperCoefficientsGiveARisingSCurveWithoutSnapThrough) {
  const MooneyRivlin law(paper_mooney_rivlin_terms());
  double min_slope = 1e300, lambda_min = 0;
  // The data of docs/validation/img/mooney_uniaxial.png.
  std::ofstream csv(test::scratch_dir("mooney_rivlin") / "mooney_uniaxial.csv");
  csv << "stretch,strain,P_law,P_closed_form,dP_dlambda\n";
  csv.precision(12);
  for (int n = 0; n <= 240; ++n) {
    const double l = 1.0 + 1.2 * n / 240;  // λ ∈ [1, 2.2]
    const double slope = uniaxial_slope(law, l);
    EXPECT_GT(slope, 0) << "λ = " << l;
    if (slope < min_slope) min_slope = slope, lambda_min = l;
    csv << l << ',' << l - 1 << ',' << eval(law, uniaxial_F(law, l)).P(0, 0) << ','
        << mooney_rivlin_nominal_stress(law.terms(), HomogeneousMode::uniaxial, l) << ',' << slope << '\n';
  }
  // S shape: stiff start (6·C10), softening to an inflection inside the range, then stiffening.
  EXPECT_NEAR(uniaxial_slope(law, 1.0), 0.6, 1e-12);
  EXPECT_GT(lambda_min, 1.3);
  EXPECT_LT(lambda_min, 1.6);
  EXPECT_LT(min_slope, 0.5 * uniaxial_slope(law, 1.0));
  EXPECT_GT(uniaxial_slope(law, 2.0), 2 * min_slope);
  // Equibiaxial and pure shear stay monotone too (biaxial example).
  for (int n = 0; n <= 200; ++n) {
    const double l = 1.0 + 1.2 * (n + 0.5) / 200, h = 1e-6;
    for (auto mode : {HomogeneousMode::equibiaxial, HomogeneousMode::pure_shear})
      EXPECT_GT(mooney_rivlin_nominal_stress(law.terms(), mode, l + h),
                mooney_rivlin_nominal_stress(law.terms(), mode, l - h));
  }
}

}  // namespace
}  // namespace tricot::fem
