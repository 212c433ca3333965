// Several materials in one specimen (docs/theory.md §5.2): fem::RegionLaws evaluates each region's law,
// names its coefficients "<region>.<coefficient>", and gives ∂P/∂c in the region's own slots.
#include "tricot/fem/region_laws.hpp"

#include <gtest/gtest.h>

#include "testing/fd_check.hpp"
#include "testing/law_eval.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/fem/neo_hookean.hpp"

namespace tricot::fem {
namespace {

constexpr double kTangentTol = 1e-7;  // central differences, h = 1e-6

// Regions 0 and 2 keep the sheet's neo-Hookean, region 1 is a Mooney–Rivlin "lesion".
RegionLaws three_regions() {
  std::vector<std::unique_ptr<Law>> laws;
  laws.push_back(std::make_unique<NeoHookean>(0.5, 1.0, Kinematics::plane_strain));
  laws.push_back(std::make_unique<MooneyRivlin>(std::vector<MooneyRivlinTerm>{{1, 0, 0.4}, {0, 1, 0.1}}));
  return RegionLaws(std::move(laws), {"", "lesion"}, {0, 1, 0});
}

LawOutput at(const Law& law, const Mat2& F, int region, bool sensitivities = false) {
  LawInput in;
  in.F = F, in.region = region;
  LawOutput out;
  law.evaluate(in, {true, sensitivities}, out);
  return out;
}

TEST(RegionLaws, EachRegionTakesItsOwnLawAndItsCoefficientsAreNamedByRegion) {
  const RegionLaws law = three_regions();
  Mat2 F;
  F << 1.3, 0.2, -0.1, 0.9;
  const NeoHookean sheet(0.5, 1.0, Kinematics::plane_strain);
  const MooneyRivlin lesion({{1, 0, 0.4}, {0, 1, 0.1}});
  EXPECT_EQ((at(law, F, 0).P - test::eval(sheet, F).P).norm(), 0);
  EXPECT_EQ((at(law, F, 2).P - test::eval(sheet, F).P).norm(), 0);
  EXPECT_EQ((at(law, F, 1).P - test::eval(lesion, F).P).norm(), 0);
  EXPECT_EQ((at(law, F, 7).P - test::eval(sheet, F).P).norm(), 0);  // no such region: the sheet's
  EXPECT_EQ(law.coefficient_names(), (std::vector<std::string>{"mu", "lambda", "lesion.C10", "lesion.C01"}));
  EXPECT_TRUE(law.linear_in_coefficients());  // both laws are linear in their coefficients
  RegionLaws copy = law;                      // a clone is independent
  copy.set_coefficients(Eigen::Vector4d(0.6, 1.1, 0.5, 0.2));
  EXPECT_EQ(law.coefficients(), Eigen::Vector4d(0.5, 1.0, 0.4, 0.1));
  EXPECT_EQ(copy.coefficients(), Eigen::Vector4d(0.6, 1.1, 0.5, 0.2));
  EXPECT_THROW(copy.set_coefficients(Eigen::Vector3d(1, 1, 1)), InputError);
  EXPECT_THROW(RegionLaws({}, {}, {}), InputError);
}

TEST(RegionLaws, CoefficientDerivativesAreEachRegionsOwnAndMatchFiniteDifferences) {
  const RegionLaws law = three_regions();
  Mat2 F;
  F << 1.4, 0.3, 0.1, 0.8;
  const Eigen::VectorXd c0 = law.coefficients();
  for (int region : {0, 1}) {
    const LawOutput out = at(law, F, region, true);
    ASSERT_EQ(out.dP_dc.size(), 4u);
    Eigen::MatrixXd J(4, 4);
    for (int k = 0; k < 4; ++k)
      for (int r = 0; r < 4; ++r) J(r, k) = out.dP_dc[static_cast<size_t>(k)](r / 2, r % 2);
    for (int k = region == 0 ? 2 : 0; k < (region == 0 ? 4 : 2); ++k) EXPECT_EQ(J.col(k).norm(), 0) << k;
    auto P_of_c = [&](const Eigen::VectorXd& c) -> Eigen::VectorXd {
      RegionLaws l = law;
      l.set_coefficients(c);
      return flatten(at(l, F, region).P);
    };
    EXPECT_TRUE(test::JacobianMatches(P_of_c, c0, J, kTangentTol)) << region;
  }
}

}  // namespace
}  // namespace tricot::fem
