#include "tricot/synth/speckle.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::synth;

namespace {

/// Pixels are float sums of exp(): two renderings of the same point agree to float round-off.
constexpr double kFloatTol = 1e-5;

SpeckleOptions one_sample() {
  SpeckleOptions o;
  o.subsamples = 1;
  return o;
}

}  // namespace

TEST(SpeckleOptions, DefaultsAreValidAndBadRadiusIsRejectedWithItsKey) {
  EXPECT_NO_THROW(SpeckleOptions{}.validate());
  SpeckleOptions o;
  o.radius = 0;
  try {
    o.validate();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "speckle.radius");
  }
}

TEST(SpecklePattern, IntensityStaysBetweenBackgroundAndBackgroundPlusContrast) {
  SpeckleOptions o;
  o.background = 0.2, o.contrast = 0.5;
  const SpecklePattern P(o, 0, 0, 100, 100);
  double lo = 1, hi = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) {
      const double v = P.intensity(Vec2(x + 0.3, y + 0.7));
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
  EXPECT_GE(lo, 0.2);
  EXPECT_LE(hi, 0.7);
  EXPECT_LT(lo, 0.25);  // there is background between the blobs ...
  EXPECT_GT(hi, 0.6);   // ... and saturated blobs
}

TEST(SpecklePattern, SameSeedGivesTheSamePatternAndAnotherSeedAnotherOne) {
  SpeckleOptions a, b;
  b.seed = 2;
  const SpecklePattern P(a, 0, 0, 50, 50), Q(a, 0, 0, 50, 50), R(b, 0, 0, 50, 50);
  EXPECT_EQ(P.intensity(Vec2(20.5, 30.25)), Q.intensity(Vec2(20.5, 30.25)));
  double diff = 0;
  for (int k = 0; k < 50; ++k) diff += std::abs(P.intensity(Vec2(k, 25)) - R.intensity(Vec2(k, 25)));
  EXPECT_GT(diff, 1.0);
}

TEST(Render, OneSamplePerPixelIsThePatternSeenThroughTheMotion) {
  const SpecklePattern P(one_sample(), -50, -50, 150, 150);
  const InverseMotion motion = [](const Vec2& x) { return Vec2(10 + (x(0) - 10) / 1.7, 0.3 * x(0) + x(1) / 0.8); };
  const image::Image img = render(P, 60, 40, motion);
  ASSERT_EQ(img.width, 60);
  ASSERT_EQ(img.height, 40);
  EXPECT_EQ(img.full_scale, 1.0);
  for (int y = 0; y < 40; y += 7)
    for (int x = 0; x < 60; x += 5)
      EXPECT_NEAR(img.at(x, y), P.intensity(motion(Vec2(x, y))), kFloatTol) << x << "," << y;
}

TEST(Render, AnIntegerTranslationShiftsTheImageExactly) {
  SpeckleOptions o;  // 4×4 sub-samples: the area average moves with the pixel grid
  const SpecklePattern P(o, -20, -20, 120, 120);
  const image::Image ref = render(P, 80, 60, no_motion);
  const image::Image cur = render(P, 80, 60, [](const Vec2& x) { return Vec2(x(0) - 3, x(1) + 2); });
  for (int y = 0; y < 50; ++y)
    for (int x = 3; x < 80; ++x) ASSERT_NEAR(cur.at(x, y), ref.at(x - 3, y + 2), kFloatTol) << x << "," << y;
}

TEST(Render, AreaAveragingSmoothsTheSampledPattern) {
  // Averaging over the pixel can only lower the pixel-to-pixel variation of a point-sampled pattern.
  SpeckleOptions fine;
  fine.radius = 1.2;
  SpeckleOptions point = fine;
  point.subsamples = 1;
  const image::Image a = render(SpecklePattern(fine, 0, 0, 64, 64), 64, 64, no_motion);
  const image::Image b = render(SpecklePattern(point, 0, 0, 64, 64), 64, 64, no_motion);
  double va = 0, vb = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 1; x < 64; ++x) {
      va += std::pow(a.at(x, y) - a.at(x - 1, y), 2);
      vb += std::pow(b.at(x, y) - b.at(x - 1, y), 2);
    }
  EXPECT_LT(va, 0.9 * vb);
}

TEST(Render, ThreadCountDoesNotChangeTheImage) {
  const SpecklePattern P(SpeckleOptions{}, 0, 0, 70, 50);
  EXPECT_EQ(render(P, 70, 50, no_motion, 1).pixels, render(P, 70, 50, no_motion, 3).pixels);
}

TEST(AddNoise, HasTheRequestedStandardDeviationAndZeroMean) {
  const image::Image flat(200, 200, 0.5f, 1.0);
  const image::Image noisy = add_noise(flat, 0.02, 7);
  double sum = 0, sum2 = 0;
  for (float v : noisy.pixels) sum += v - 0.5, sum2 += (v - 0.5) * (v - 0.5);
  const double n = double(noisy.pixels.size());
  // 40 000 samples: the sample mean is within 4σ/√n = 4e-4 and the deviation within about 1.5 %
  EXPECT_NEAR(sum / n, 0.0, 4e-4);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 0.02 * 0.015);
  EXPECT_EQ(add_noise(flat, 0.02, 7).pixels, noisy.pixels);  // the seed fixes the noise
}

// A knit (wales along y) repeats every stitch: 4 r across the wales, 3.2 r along them. The mean
// autocorrelation of the image over the rows (columns) peaks at that lag, well above half of it.
TEST(KnitTexture, RepeatsAtTheStitchPitchAcrossAndAlongTheWales) {
  SpeckleOptions o = one_sample();
  o.texture = Texture::knit;
  o.radius = 5;
  const int n = 240;
  const SpecklePattern P(o, 0, 0, n, n);
  const image::Image img = render(P, n, n, no_motion);
  // Normalised autocorrelation at an integer lag along x (dx = 1) or y.
  const auto autocorrelation = [&](int lag, bool along_x) {
    double mean = 0;
    for (float v : img.pixels) mean += v;
    mean /= img.pixels.size();
    double num = 0, den = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double a = img.at(x, y) - mean;
        den += a * a;
        const int xs = along_x ? x + lag : x, ys = along_x ? y : y + lag;
        if (xs < n && ys < n) num += a * (img.at(xs, ys) - mean);
      }
    return num / den;
  };
  const int across = 20, along = 16;  // 4 r and 3.2 r
  EXPECT_GT(autocorrelation(across, true), autocorrelation(across * 3 / 4, true) + 0.1);
  EXPECT_GT(autocorrelation(along, false), autocorrelation(along / 2, false) + 0.1);
  EXPECT_GT(autocorrelation(across, true), 0.2);
  EXPECT_GT(autocorrelation(along, false), 0.2);
}

TEST(KnitTexture, TheConfigWordsNameTheTextures) {
  EXPECT_EQ(texture_from_string("knit"), Texture::knit);
  EXPECT_EQ(texture_from_string(to_string(Texture::speckle)), Texture::speckle);
  EXPECT_FALSE(texture_from_string("Knit").has_value());
}

namespace {

/// The B-spline table's largest error on the knit and the round speckle of 2.5 px radius (measured
/// 2.5e-3 and 3.1e-3 of full scale at 2e5 random points, on the fuzz's smallest blobs) ...
constexpr double kTableTol = 5e-3;
/// ... and its RMS error (measured 4.0e-5 and 4.5e-5: 0.01 gray level of 255).
constexpr double kTableRms = 1e-4;

SpeckleOptions texture(Texture t) {
  SpeckleOptions o;
  o.texture = t;
  o.radius = 2.5;
  o.wale_angle_deg = t == Texture::knit ? -60 : 90;
  return o;
}

}  // namespace

TEST(SpecklePattern, IntensityGridHoldsTheIntensityAtItsNodes) {
  for (Texture t : {Texture::speckle, Texture::knit}) {
    const SpecklePattern P(texture(t), 0, 0, 80, 60);
    const double x0 = -3.1, y0 = 2.3, h = 0.37;
    const image::Image grid = P.intensity_grid(x0, y0, h, 240, 150);
    for (int j = 0; j < 150; j += 7)
      for (int i = 0; i < 240; i += 3)
        ASSERT_NEAR(grid.at(i, j), P.intensity(Vec2(x0 + i * h, y0 + j * h)), kFloatTol) << i << ", " << j;
  }
}

TEST(PatternTable, IsThePatternWithinItsBSplineErrorAndThePatternItselfOffItsGrid) {
  for (Texture t : {Texture::speckle, Texture::knit}) {
    const SpecklePattern P(texture(t), 0, 0, 300, 300);
    const PatternTable table(P, 0, 0, 300, 300);
    EXPECT_EQ(table.step(), 0.25);  // min(¼ px, 0.45 × the smallest radius: 0.79 px on the knit's fuzz)
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 300);
    double max = 0, s2 = 0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
      const Vec2 X(u(rng), u(rng));
      const double d = table.intensity(X) - P.intensity(X);
      max = std::max(max, std::abs(d));
      s2 += d * d;
    }
    EXPECT_LT(max, kTableTol) << to_string(t);
    EXPECT_LT(std::sqrt(s2 / n), kTableRms) << to_string(t);
    // Beyond the rectangle and its one-node border: the pattern's own value.
    for (const Vec2& X : {Vec2(-5, 10), Vec2(150, 306), Vec2(301, 301)}) EXPECT_EQ(table.intensity(X), P.intensity(X));
  }
}

TEST(PatternTable, AGridBeyondItsNodeLimitIsNotMadeAndThePatternAnswers) {
  SpeckleOptions o;
  o.radius = 0.2;  // step 0.45 × 0.14 px: 300 px need 4 760² nodes, beyond kMaxNodes
  const SpecklePattern P(o, 0, 0, 300, 300);
  const PatternTable table(P, 0, 0, 300, 300);
  EXPECT_EQ(table.step(), 0.0);
  for (const Vec2& X : {Vec2(10.3, 20.7), Vec2(150, 150.1)}) EXPECT_EQ(table.intensity(X), P.intensity(X));
}
