#include "tricot/dic/overlay.hpp"

#include <gtest/gtest.h>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::dic;

namespace {

/// A 200×100 gray image and a frame in which the left grid points moved 2 px right and the rest 4 px.
struct Case {
  image::Image img{200, 100, 0.5f, 1.0};
  std::vector<GridPoint> grid = make_grid(Roi::whole_image(), 200, 100, 21, 20);
  TrackedFrame f;
  Case() {
    for (int y = 0; y < 100; ++y)
      for (int x = 0; x < 200; ++x) img.at(x, y) = float((x * 7 + y * 13) % 17) / 17.0f;  // some texture
    const std::size_t n = grid.size();
    f.frame = 3;
    f.x.resize(n), f.zncc.assign(n, 0.99), f.status.assign(n, PointStatus::ok), f.strain.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      f.x[k] = grid[k].x + Vec2(grid[k].x(0) < 100 ? 2 : 4, 0);
      f.strain[k].valid = true;
    }
  }
};

std::array<int, 3> pixel(const image::RgbImage& img, int x, int y) {
  const std::uint8_t* p = &img.rgb[3 * (std::size_t(y) * img.width + x)];
  return {p[0], p[1], p[2]};
}

bool gray(const std::array<int, 3>& c) { return c[0] == c[1] && c[1] == c[2]; }

}  // namespace

TEST(Overlay, TwoByTwoPanelsOfTheImageWithAStripBelowEach) {
  Case c;
  const image::RgbImage out = draw_overlay(c.img, c.grid, 20, c.f);
  // 4 panels, two per row, 4 px apart; each is the image plus a 34 px strip
  EXPECT_EQ(out.width, 2 * 200 + 4);
  EXPECT_EQ(out.height, 2 * (100 + 34) + 4);
}

TEST(Overlay, PointsAreColouredByTheirValueAndTheRestStaysGray) {
  Case c;
  OverlayOptions o;
  o.panels = {OverlayField::displacement};
  o.opacity = 1.0;
  const image::RgbImage out = draw_overlay(c.img, c.grid, 20, c.f, o);
  ASSERT_EQ(out.width, 200);
  // a point on the left (|u| = 2, the low end) and one on the right (|u| = 4, the high end) differ
  const auto left = pixel(out, static_cast<int>(c.f.x[0](0)), static_cast<int>(c.f.x[0](1)));
  const auto right =
      pixel(out, static_cast<int>(c.f.x[c.grid.size() - 1](0)), static_cast<int>(c.f.x[c.grid.size() - 1](1)));
  EXPECT_FALSE(gray(left));
  EXPECT_FALSE(gray(right));
  EXPECT_NE(left, right);
  EXPECT_EQ(pixel(out, 100, 101), (std::array<int, 3>{32, 32, 32}));  // the strip below the image
}

TEST(Overlay, LargeImagesAreScaledDownToThePanelWidth) {
  Case c;
  OverlayOptions o;
  o.panels = {OverlayField::zncc, OverlayField::exx, OverlayField::u};
  o.panel_width = 100;
  const image::RgbImage out = draw_overlay(c.img, c.grid, 20, c.f, o);
  EXPECT_EQ(out.width, 2 * 100 + 4);
  EXPECT_EQ(out.height, 2 * (50 + 34) + 4);
}

TEST(OverlayOptions, ATinyPanelIsRejectedWithItsKey) {
  OverlayOptions o;
  o.panel_width = 10;
  try {
    o.validate();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "output.panel_width");
  }
}
