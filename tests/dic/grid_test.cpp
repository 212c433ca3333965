#include "tricot/dic/grid.hpp"

#include <gtest/gtest.h>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::dic;

TEST(Grid, RectangleGridKeepsWholeSubsetsInsideTheImage) {
  // 100×80 image, 21 px subsets (half 10), step 10: x ∈ {10, ..., 89} → 10..80, y ∈ 10..69 → 10..60
  const auto g = make_grid(Roi::whole_image(), 100, 80, 21, 10);
  EXPECT_EQ(g.size(), 8u * 6u);
  EXPECT_EQ(g.front().x, Vec2(10, 10));
  EXPECT_EQ(g.back().x, Vec2(80, 60));
  EXPECT_EQ(g.back().i, 7);
  EXPECT_EQ(g.back().j, 5);
}

TEST(Grid, RectangleRoiIsInclusiveOfItsCorners) {
  const auto g = make_grid(Roi::rectangle(30, 20, 50, 40), 100, 80, 11, 10);
  ASSERT_EQ(g.size(), 9u);
  EXPECT_EQ(g.front().x, Vec2(30, 20));
  EXPECT_EQ(g.back().x, Vec2(50, 40));
}

TEST(Grid, PolygonRoiKeepsOnlyCentresInside) {
  // triangle with the right angle at (20, 20): points with x + y ≤ 80 (strictly inside or on two edges)
  const auto g = make_grid(Roi::from_polygon({{20, 20}, {60.5, 20}, {20, 60.5}}), 100, 100, 11, 10);
  for (const auto& p : g) EXPECT_LE(p.x(0) + p.x(1), 80.5);
  EXPECT_EQ(g.size(), 5u + 4u + 3u + 2u + 1u);
}

TEST(Grid, MaskRoiUsesPixelsAboveHalfScale) {
  image::Image m(60, 60, 0.0f, 255.0);
  for (int y = 0; y < 60; ++y)
    for (int x = 30; x < 60; ++x) m.at(x, y) = 255;
  const auto g = make_grid(Roi::from_mask(m), 60, 60, 11, 5);
  for (const auto& p : g) EXPECT_GE(p.x(0), 30);
  EXPECT_FALSE(g.empty());
}

TEST(Grid, RoiOutsideTheImageIsAnInputErrorSayingSo) {
  try {
    make_grid(Roi::rectangle(200, 200, 300, 300), 100, 80, 21, 10);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "dic.roi: region of interest lies outside the image (got 200,200,300,300, expected within 0,0,99,79)");
  }
}

TEST(Grid, RoiTooSmallForOneSubsetIsAnInputError) {
  EXPECT_THROW(make_grid(Roi::rectangle(0, 0, 5, 5), 100, 80, 21, 10), InputError);
}

TEST(Grid, NeighboursAreTheFourAdjacentGridPoints) {
  const auto g = make_grid(Roi::whole_image(), 100, 80, 21, 10);
  const auto nb = grid_neighbours(g);
  // point (i=1, j=1) is index 1·8 + 1 = 9
  EXPECT_EQ(nb[9][0], 10);
  EXPECT_EQ(nb[9][1], 8);
  EXPECT_EQ(nb[9][2], 17);
  EXPECT_EQ(nb[9][3], 1);
  EXPECT_EQ(nb[0][1], -1);
  EXPECT_EQ(nb[0][3], -1);
}
