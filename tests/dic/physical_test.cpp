#include "tricot/dic/physical.hpp"

#include <gtest/gtest.h>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::dic;

namespace {
constexpr double kExact = 1e-12;  ///< rotations by multiples of 90° are exact up to round-off
}

TEST(PhysicalFrame, CentrePixelIsTheOriginAndImageUpIsSpecimenPlusY) {
  PhysicalFrame p;
  p.mm_per_px = 0.1;
  p.centre_px = Vec2(500, 400);
  EXPECT_LT(p.point(Vec2(500, 400)).norm(), kExact);
  EXPECT_LT((p.point(Vec2(510, 400)) - Vec2(1, 0)).norm(), kExact);  // 10 px right = +1 mm X
  EXPECT_LT((p.point(Vec2(500, 390)) - Vec2(0, 1)).norm(), kExact);  // 10 px up on screen = +1 mm Y
}

TEST(PhysicalFrame, AxesTurnedNinetyDegreesSwapTheStrains) {
  PhysicalFrame p;
  p.angle_deg = 90;  // specimen X points up on screen
  EXPECT_LT((p.vector(Vec2(0, -1)) - Vec2(1, 0)).norm(), kExact);
  Mat2 E;
  E << 0.5, 0.1, 0.1, 0.2;
  const Mat2 Es = p.tensor(E);
  EXPECT_NEAR(Es(0, 0), 0.2, kExact);
  EXPECT_NEAR(Es(1, 1), 0.5, kExact);
  EXPECT_NEAR(std::abs(Es(0, 1)), 0.1, kExact);
}

TEST(PhysicalFrame, ShearChangesSignWhenYIsFlippedUp) {
  PhysicalFrame p;
  Mat2 E;
  E << 0.0, 0.1, 0.1, 0.0;
  EXPECT_NEAR(p.tensor(E)(0, 1), -0.1, kExact);
  p.y_up = false;
  EXPECT_NEAR(p.tensor(E)(0, 1), 0.1, kExact);
}

TEST(PhysicalFrame, NonPositivePixelSizeIsRejected) {
  PhysicalFrame p;
  p.mm_per_px = 0;
  EXPECT_THROW(p.validate(), InputError);
}
