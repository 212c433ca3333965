#include "tricot/dic/seed.hpp"

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tricot/dic/correlate.hpp"
#include "tricot/dic/grid.hpp"
#include "tricot/synth/speckle.hpp"

using namespace tricot;
using namespace tricot::dic;

namespace {

/// Noise-free rendered images: IC-GN's own error (see correlate_test.cpp).
constexpr double kNoiseFreeTol = 5e-3;

synth::SpeckleOptions speckle() {
  synth::SpeckleOptions o;
  o.subsamples = 2;
  return o;
}

/// x = (λx X, c_y + λy (Y − c_y)): a strip stretched from its left end, as in the tension series.
struct Tension {
  double lx, ly;
  double cy;
  Vec2 forward(const Vec2& X) const { return Vec2(lx * X(0), cy + ly * (X(1) - cy)); }
  Vec2 inverse(const Vec2& x) const { return Vec2(x(0) / lx, cy + (x(1) - cy) / ly); }
};

}  // namespace

TEST(IntegerSearch, FindsAnIntegerShiftWithZnccOne) {
  const synth::SpecklePattern P(speckle(), -20, -20, 140, 120);
  const image::Image f = synth::render(P, 120, 100, synth::no_motion);
  const image::Image g = synth::render(P, 120, 100, [](const Vec2& x) { return Vec2(x(0) - 7, x(1) + 4); });
  const IntegerMatch m = integer_search(f, g, Vec2(50, 50), 31, Vec2::Zero(), 10);
  ASSERT_TRUE(m.found);
  EXPECT_EQ(m.displacement, Vec2(7, -4));
  EXPECT_GT(m.zncc, 0.9999);
}

TEST(IntegerSearch, ABlankSubsetFindsNothing) {
  const image::Image blank(80, 80, 0.5f, 1.0);
  EXPECT_FALSE(integer_search(blank, blank, Vec2(40, 40), 21, Vec2::Zero(), 5).found);
}

TEST(SeedGuess, SatellitesGiveTheDisplacementGradient) {
  // 10 % stretch along x about x = 0: satellites one subset (31 px) away see ±3.1 px more
  const synth::SpecklePattern P(speckle(), -20, -20, 260, 140);
  const Frame f = prepare_frame(synth::render(P, 240, 120, synth::no_motion));
  const Frame g = prepare_frame(synth::render(P, 240, 120, [](const Vec2& x) { return Vec2(x(0) / 1.1, x(1)); }));
  const SeedGuess s = seed_guess(f, g, Vec2(100, 60), 31, 20);
  ASSERT_TRUE(s.found);
  EXPECT_NEAR(s.p(0), 10, 1.0);        // integer start: within a pixel
  EXPECT_NEAR(s.p(1), 0.1, 1.0 / 31);  // integer satellites: within a pixel over 31 px
  EXPECT_NEAR(s.p(8), 0.0, 1.0 / 31);
}

TEST(WideSeedGuess, FindsAFortyFivePercentStretchFarBeyondTheSearchRadius) {
  const Tension t{1.45, 0.85, 100};
  const synth::SpecklePattern P(speckle(), -20, -20, 720, 220);
  const Frame f = prepare_frame(synth::render(P, 700, 200, synth::no_motion));
  const Frame g = prepare_frame(synth::render(P, 700, 200, [&](const Vec2& x) { return t.inverse(x); }));
  const Vec2 X(300, 100);  // moves by 135 px
  EXPECT_NE(icgn(f, g, X, seed_guess(f, g, X, 31, 50).p, IcgnOptions{}).status, PointStatus::ok);
  const SeedGuess s = wide_seed_guess(f, g, X, 31);
  ASSERT_TRUE(s.found);
  EXPECT_NEAR(s.p(0), t.forward(X)(0) - X(0), 2.0);
  EXPECT_NEAR(s.p(1), 0.45, 0.07);  // the fine grid of stretches is 6 % apart
  EXPECT_NEAR(s.p(8), -0.15, 0.07);
  const PointMatch m = icgn(f, g, X, s.p, IcgnOptions{});
  ASSERT_EQ(m.status, PointStatus::ok);
  EXPECT_NEAR(m.p(0), t.forward(X)(0) - X(0), kNoiseFreeTol);
  EXPECT_NEAR(m.p(1), 0.45, 1e-3);
}

// The free edge of a knit strip turns as it shrinks: a 25° rotation with a 30 % stretch about a point
// 60 px away, in one step. Neither the local search nor unrotated templates find it.
TEST(WideSeedGuess, FindsARotationOfTwentyFiveDegreesWithAStretch) {
  const double th = 25 * std::numbers::pi / 180;
  Mat2 F;
  F << 1.3 * std::cos(th), -std::sin(th), 1.3 * std::sin(th), std::cos(th);  // R(θ) · diag(1.3, 1)
  const Vec2 c(200, 150);
  const Mat2 Finv = F.inverse();
  const synth::SpecklePattern P(speckle(), -20, -20, 420, 320);
  const Frame f = prepare_frame(synth::render(P, 400, 300, synth::no_motion));
  const Frame g = prepare_frame(synth::render(P, 400, 300, [&](const Vec2& x) { return Vec2(c + Finv * (x - c)); }));
  const Vec2 X(160, 110);
  const Vec2 u = F * (X - c) + c - X;
  EXPECT_NE(icgn(f, g, X, seed_guess(f, g, X, 31, 50).p, IcgnOptions{}).status, PointStatus::ok);
  const SeedGuess s = wide_seed_guess(f, g, X, 31);
  ASSERT_TRUE(s.found);
  EXPECT_NEAR(s.p(0), u(0), 2.0);
  EXPECT_NEAR(s.p(6), u(1), 2.0);
  const PointMatch m = icgn(f, g, X, s.p, IcgnOptions{});
  ASSERT_EQ(m.status, PointStatus::ok);
  EXPECT_NEAR(m.p(0), u(0), kNoiseFreeTol);
  EXPECT_NEAR(m.p(6), u(1), kNoiseFreeTol);
  EXPECT_NEAR(m.p(7), F(1, 0), 1e-3);  // ∂v/∂x = 1.3 sin θ
}

TEST(WideSeedGuess, ABlankImageFindsNothing) {
  const synth::SpecklePattern P(speckle(), 0, 0, 100, 100);
  const Frame f = prepare_frame(synth::render(P, 100, 100, synth::no_motion));
  const Frame blank = prepare_frame(image::Image(100, 100, 0.2f, 1.0));
  EXPECT_FALSE(wide_seed_guess(f, blank, Vec2(50, 50), 21).found);
}

TEST(CorrelatePair, AFortyFivePercentStretchInOneStepIsSeededByTheWideSearch) {
  const Tension t{1.45, 0.85, 100};
  const synth::SpecklePattern P(speckle(), -20, -20, 720, 220);
  const Frame f = prepare_frame(synth::render(P, 700, 200, synth::no_motion));
  const Frame g = prepare_frame(synth::render(P, 700, 200, [&](const Vec2& x) { return t.inverse(x); }));
  const auto grid = make_grid(Roi::rectangle(20, 40, 460, 160), 700, 200, 31, 20);
  std::vector<Vec2> c;
  for (const auto& p : grid) c.push_back(p.x);
  const PairResult r = correlate_pair(f, g, c, grid_neighbours(grid), DicOptions{});
  EXPECT_NE(r.message.find("wide search"), std::string::npos) << r.message;
  EXPECT_EQ(r.ok, static_cast<int>(c.size())) << r.message;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (r.points[k].status != PointStatus::ok) continue;
    const Vec2 u = t.forward(c[k]) - c[k];
    EXPECT_NEAR(r.points[k].p(0), u(0), kNoiseFreeTol) << c[k].transpose();
    EXPECT_NEAR(r.points[k].p(6), u(1), kNoiseFreeTol) << c[k].transpose();
  }
}
