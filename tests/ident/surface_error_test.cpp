#include "tricot/ident/surface_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::ident;

namespace {
/// Sums of a few exact ratios: round-off only.
constexpr double kRoundOff = 1e-14;
}  // namespace

// A surface that is everywhere 1.2× the data has ē = 0.2 exactly; points outside the practical
// domain count only in the whole-range mean.
TEST(Eq9Error, IsTheMeanRelativeDistanceOverTheWholeAndThePracticalRange) {
  std::vector<SurfacePoint> points = {{0.1, 0.0, 0.02}, {0.7, 0.3, 0.2}, {0.9, 0.25, 0.3}, {0.5, 0.5, 0.1}};
  auto data_at = [&](double eC, double eW) {
    for (const auto& p : points)
      if (p.eC == eC && p.eW == eW) return p.force;
    return 0.0;
  };
  // 1.2× in the practical domain, 0.5× outside: ē_practical = 0.2, ē_whole = (0.2 + 0.2 + 0.5 + 0.5)/4.
  auto identified = [&](double eC, double eW) {
    return (StrainDomain{}.contains(eC, eW) ? 1.2 : 0.5) * data_at(eC, eW);
  };
  const Eq9Error e = eq9_error(points, identified);
  EXPECT_EQ(e.points_whole, 4);
  EXPECT_EQ(e.points_practical, 2);
  EXPECT_NEAR(e.practical, 0.2, kRoundOff);
  EXPECT_NEAR(e.whole, 0.35, kRoundOff);
}

TEST(Eq9Error, LeavesOutPointsWithoutForceAndRejectsAPracticalDomainOutsideTheData) {
  const std::vector<SurfacePoint> points = {{0.0, 0.0, 0.0}, {0.2, 0.1, 0.05}};
  auto same = [](double, double) { return 0.05; };
  try {
    eq9_error(points, same);
    FAIL() << "no point in [60, 100] % x [20, 40] %";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("eq9.practical"), std::string::npos) << e.what();
  }
  StrainDomain d;
  d.eC_min = 0.1, d.eC_max = 0.3, d.eW_min = 0, d.eW_max = 0.2;
  const Eq9Error e = eq9_error(points, same, d);
  EXPECT_EQ(e.points_whole, 1);
  EXPECT_EQ(e.whole, 0.0);
  d.eC_min = 0.5;  // min > max
  EXPECT_THROW(eq9_error(points, same, d), InputError);
}
