// The paper's case at full length (issue 5): a 100-frame sequence to 120 % stretch along x and 40 %
// along y, tracked in incremental mode. Prints the error per frame (docs/validation.md).
#include <gtest/gtest.h>

#include <cstdio>

#include "stretch_sequence.hpp"

using namespace tricot;
using namespace tricot::dic;
using test::StretchSequence;

namespace {
/// The bound: tracked points end within 0.05 px RMS of the truth.
constexpr double kTrackingTol = 0.05;
}  // namespace

TEST(SequenceLong, HundredFramesTo120And40PercentEndWithin005PxRmsAndDriftNoFasterThanSqrtN) {
  // The engine's default (first order) and tricot dic's (issue 16: `order = "auto"`, second order where
  // the F-test says it pays).
  for (const ShapeOrder order : {ShapeOrder::first, ShapeOrder::automatic}) {
    const char* name = order == ShapeOrder::first ? "first" : "auto";
    StretchSequence s;
    s.frames = 100;
    SequenceOptions o;
    o.mode = SequenceMode::incremental;
    o.dic.icgn.order = order;
    const SequenceResult r = test::track(s, o);
    ASSERT_EQ(r.frames.size(), 101u);
    std::printf("order %s\nframe  rms_px   points_ok\n", name);
    for (int k = 10; k <= 100; k += 10) {
      const auto [rms, ok] = test::rms_error(s, r, k);
      std::printf("%5d  %.5f  %d/%zu\n", k, rms, ok, r.grid.size());
    }
    const auto [rms100, ok] = test::rms_error(s, r, 100);
    EXPECT_EQ(ok, static_cast<int>(r.grid.size())) << name;
    EXPECT_LT(rms100, kTrackingTol) << name;

    // The same final state in 10 increments: 10 times more increments may cost at most √10 times the error.
    StretchSequence coarse = s;
    coarse.frames = 10;
    const double rms10 = test::rms_error(coarse, test::track(coarse, o), 10).first;
    std::printf("same final stretch: 10 increments %.5f px, 100 increments %.5f px (ratio %.2f, sqrt(10) = 3.16)\n",
                rms10, rms100, rms100 / rms10);
    EXPECT_LE(rms100, std::sqrt(10.0) * rms10) << name;
  }
}
