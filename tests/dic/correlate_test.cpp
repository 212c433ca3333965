#include "tricot/dic/correlate.hpp"

#include <gtest/gtest.h>

#include "tricot/dic/grid.hpp"
#include "tricot/synth/speckle.hpp"

using namespace tricot;
using namespace tricot::dic;

namespace {

/// Noise-free rendered images: the B-spline interpolation error of a 2.5 px speckle spreads over
/// ±0.004 px from subset to subset (3σ).
constexpr double kNoiseFreeTol = 5e-3;

struct Case {
  Frame f, g;
  std::vector<GridPoint> grid;
  std::vector<Vec2> centres;
  std::vector<std::array<int, 4>> nb;
};

Case make_case(int w, int h, const synth::InverseMotion& motion, const Roi& roi, int step,
               synth::SpeckleOptions so = {}) {
  const synth::SpecklePattern P(so, -w, -h, 2 * w, 2 * h);
  Case c{prepare_frame(synth::render(P, w, h, synth::no_motion)),
         prepare_frame(synth::render(P, w, h, motion)),
         {},
         {},
         {}};
  c.grid = make_grid(roi, w, h, 31, step);
  for (const auto& p : c.grid) c.centres.push_back(p.x);
  c.nb = grid_neighbours(c.grid);
  return c;
}

}  // namespace

TEST(CorrelatePair, FindsALargeTranslationFromOneSeedAndPropagatesEverywhere) {
  const Vec2 d(23.4, -17.8);
  Case c = make_case(
      240, 200, [&](const Vec2& x) { return Vec2(x - d); }, Roi::rectangle(20, 40, 200, 160), 15);
  const PairResult r = correlate_pair(c.f, c.g, c.centres, c.nb, DicOptions{});
  EXPECT_EQ(r.ok, static_cast<int>(c.centres.size())) << r.message;
  EXPECT_EQ(r.seeds_tried, 1);
  for (const auto& m : r.points) {
    EXPECT_NEAR(m.p(0), d(0), kNoiseFreeTol);
    EXPECT_NEAR(m.p(6), d(1), kNoiseFreeTol);
  }
}

TEST(CorrelatePair, MeasuresAUniformFivePercentStrainInOneStep) {
  const Vec2 c0(120, 100);
  Case c = make_case(
      240, 200, [&](const Vec2& x) { return Vec2(c0(0) + (x(0) - c0(0)) / 1.05, c0(1) + (x(1) - c0(1)) / 1.02); },
      Roi::whole_image(), 10);
  const PairResult r = correlate_pair(c.f, c.g, c.centres, c.nb, DicOptions{});
  int inside = 0;
  for (std::size_t k = 0; k < c.centres.size(); ++k) {
    const Vec2 X = c.centres[k];
    const Vec2 u(0.05 * (X(0) - c0(0)), 0.02 * (X(1) - c0(1)));
    // subsets near the left/right border are pushed out of the image by the stretch
    if (r.points[k].status == PointStatus::out_of_image) continue;
    ASSERT_EQ(r.points[k].status, PointStatus::ok)
        << X.transpose() << " " << to_string(r.points[k].status) << " " << r.message;
    ++inside;
    EXPECT_NEAR(r.points[k].p(0), u(0), kNoiseFreeTol);
    EXPECT_NEAR(r.points[k].p(6), u(1), kNoiseFreeTol);
    EXPECT_NEAR(r.points[k].p(1), 0.05, 2e-4);
  }
  EXPECT_GT(inside, static_cast<int>(c.centres.size()) / 2);
}

TEST(CorrelatePair, SeedOnABlankAreaIsReportedAndTheNextSeedTakesOver) {
  // The left half of the image is blank (a flat gray level); the user's seed lies there.
  const Vec2 d(1.3, 0.6);
  synth::SpeckleOptions so;
  Case c = make_case(
      240, 160, [&](const Vec2& x) { return Vec2(x - d); }, Roi::whole_image(), 10, so);
  for (Frame* fr : {&c.f, &c.g}) {
    for (int y = 0; y < 160; ++y)
      for (int x = 0; x < 110; ++x) fr->image.at(x, y) = 0.5f;
    *fr = prepare_frame(fr->image);
  }
  DicOptions o;
  o.seeds = {Vec2(40, 80)};
  const PairResult r = correlate_pair(c.f, c.g, c.centres, c.nb, o);
  EXPECT_NE(r.message.find("seed 1 at (35, 75): no_texture"), std::string::npos) << r.message;
  EXPECT_GE(r.seeds_tried, 2);
  for (std::size_t k = 0; k < c.centres.size(); ++k) {
    const double x = c.centres[k](0);
    if (x + 15 < 110) {
      EXPECT_EQ(r.points[k].status, PointStatus::no_texture) << x;
    } else if (x - 15 > 110) {
      ASSERT_EQ(r.points[k].status, PointStatus::ok) << x;
      EXPECT_NEAR(r.points[k].p(0), d(0), kNoiseFreeTol);
    }
  }
}

TEST(CorrelatePair, BlankCurrentImageGivesNoGoodPointAndNoCrash) {
  Case c = make_case(160, 120, synth::no_motion, Roi::whole_image(), 20);
  const Frame blank = prepare_frame(image::Image(160, 120, 0.3f));
  const PairResult r = correlate_pair(c.f, blank, c.centres, c.nb, DicOptions{});
  EXPECT_EQ(r.ok, 0);
  for (const auto& m : r.points) EXPECT_NE(m.status, PointStatus::ok);
}

TEST(CorrelatePair, GuessesAreUsedAndFailuresRecoveredByPropagation) {
  const Vec2 d(4.2, 2.1);
  Case c = make_case(
      200, 160, [&](const Vec2& x) { return Vec2(x - d); }, Roi::rectangle(20, 20, 175, 135), 15);
  std::vector<std::optional<Shape>> guesses(c.centres.size(), translation(4, 2));
  guesses[3] = translation(60, -40);  // hopeless guess: must be recovered from a neighbour
  guesses[7] = std::nullopt;          // no guess at all
  const PairResult r = correlate_pair(c.f, c.g, c.centres, c.nb, DicOptions{}, guesses);
  EXPECT_EQ(r.ok, static_cast<int>(c.centres.size())) << r.message;
  EXPECT_EQ(r.seeds_tried, 0);
  EXPECT_NEAR(r.points[3].p(0), d(0), kNoiseFreeTol);
  EXPECT_NEAR(r.points[7].p(6), d(1), kNoiseFreeTol);
}
