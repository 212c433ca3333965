#include "tricot/dic/sequence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "stretch_sequence.hpp"
#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::dic;
using test::StretchSequence;

namespace {

/// The bound for tracked points at the end of the sequence (0.05 px RMS); noise-free rendered
/// images do about 30 times better, so the quick tests hold them to a fifth of it.
constexpr double kTrackingTol = 0.01;
/// Green–Lagrange strain from the plane fit: 5×5 points, each within ~1e-3 px, 10 px apart.
constexpr double kStrainTol = 1e-3;

SequenceOptions options(SequenceMode mode) {
  SequenceOptions o;
  o.mode = mode;
  return o;
}

}  // namespace

TEST(Sequence, ABriefReportCountsTheFramesUpToTheLastOneKeptOrNot) {
  SequenceResult r;
  r.grid.resize(25);
  r.seconds = 2.1;
  EXPECT_EQ(r.brief_report(), "0 frames, 25 points, 2.1 s");
  TrackedFrame last;
  last.frame = 40;  // only the last frame kept (keep_frames = false, or a resumed run)
  last.ok = 24;
  last.mean_zncc = 0.99871;
  r.frames.push_back(last);
  EXPECT_EQ(r.brief_report(), "41 frames, 25 points: 24/25 ok in the last frame, mean ZNCC 0.9987, 2.1 s");
}

TEST(Sequence, IncrementalModeTracksAStretchTo120And40PercentInTenFrames) {
  StretchSequence s;  // 12 % stretch per frame along x, 4 % along y
  const SequenceResult r = test::track(s, options(SequenceMode::incremental));
  ASSERT_EQ(r.frames.size(), 11u);
  EXPECT_EQ(r.termination, SequenceTermination::completed);
  const auto [rms, ok] = test::rms_error(s, r, s.frames);
  EXPECT_EQ(ok, static_cast<int>(r.grid.size())) << r.frames.back().message;
  EXPECT_LT(rms, kTrackingTol);
  for (const TrackedFrame& f : r.frames) EXPECT_EQ(f.reference_frame, std::max(0, f.frame - 1));
  // the strain of the whole stretch, relative to frame 0
  const StrainPoint& e = r.frames.back().strain[r.grid.size() / 2];
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.exx, 0.5 * (2.2 * 2.2 - 1), kStrainTol);
  EXPECT_NEAR(e.eyy, 0.5 * (1.4 * 1.4 - 1), kStrainTol);
  EXPECT_NEAR(e.exy, 0.0, kStrainTol);
}

// The rig's transverse setting moves the whole field by tens of pixels in the first step, then the
// pull adds little per step: the previous increment, the incremental mode's guess for the next one,
// is then wrong at every point. The points must be found again from seeds, not all lost.
TEST(Sequence, IncrementalModeRecoversWhenEveryVelocityGuessIsWrong) {
  StretchSequence s;
  s.final_stretch = Vec2(1.1, 1.0);
  s.frames = 3;
  s.shifts = {Vec2::Zero(), Vec2(24, 0), Vec2(24, 0), Vec2(24, 0)};
  const SequenceResult r = test::track(s, options(SequenceMode::incremental));
  ASSERT_EQ(r.frames.size(), 4u);
  EXPECT_EQ(r.termination, SequenceTermination::completed);
  const auto [rms, ok] = test::rms_error(s, r, s.frames);
  EXPECT_EQ(ok, static_cast<int>(r.grid.size())) << r.frames[2].message;
  EXPECT_LT(rms, kTrackingTol);
}

// A knit's natural tracers repeat every stitch (10 px here): a look-alike subset sits one pitch
// away. A 24 px first step (2.4 pitches) followed by small ones must still be tracked to the truth,
// not to a neighbouring stitch.
TEST(Sequence, IncrementalModeTracksAKnitTextureWithoutSlippingAStitch) {
  StretchSequence s;
  s.speckle.texture = synth::Texture::knit;
  s.final_stretch = Vec2(1.3, 1.1);
  s.frames = 4;
  s.shifts = {Vec2::Zero(), Vec2(24, 0), Vec2(24, 0), Vec2(24, 0), Vec2(24, 0)};
  const SequenceResult r = test::track(s, options(SequenceMode::incremental));
  EXPECT_EQ(r.termination, SequenceTermination::completed);
  const auto [rms, ok] = test::rms_error(s, r, s.frames);
  EXPECT_EQ(ok, static_cast<int>(r.grid.size())) << r.frames.back().message;
  EXPECT_LT(rms, kTrackingTol);
}

TEST(Sequence, DriftGrowsNoFasterThanTheSquareRootOfTheNumberOfIncrements) {
  // The same final deformation reached in 5 and in 20 increments: independent errors per increment
  // would make the second 2 = √4 times larger, a bias repeated at every increment 4 times larger.
  StretchSequence s;
  s.final_stretch = Vec2(1.5, 1.2);
  s.frames = 5;
  const double coarse = test::rms_error(s, test::track(s, options(SequenceMode::incremental)), 5).first;
  s.frames = 20;
  const double fine = test::rms_error(s, test::track(s, options(SequenceMode::incremental)), 20).first;
  EXPECT_LT(coarse, kTrackingTol);
  EXPECT_LE(fine, std::sqrt(20.0 / 5.0) * coarse)
      << "5 increments: " << coarse << " px, 20 increments: " << fine << " px";
}

TEST(Sequence, ReferenceModeCorrelatesEveryFrameWithTheFirst) {
  StretchSequence s;
  s.final_stretch = Vec2(1.3, 1.1);
  s.frames = 3;
  const SequenceResult r = test::track(s, options(SequenceMode::reference));
  for (const TrackedFrame& f : r.frames) EXPECT_EQ(f.reference_frame, 0);
  const auto [rms, ok] = test::rms_error(s, r, s.frames);
  EXPECT_EQ(ok, static_cast<int>(r.grid.size()));
  EXPECT_LT(rms, kTrackingTol);
}

TEST(Sequence, AutoModeMovesTheReferenceWhenTheCorrelationDrops) {
  // Against frame 0, subsets near the ROI's ends leave the image at 120 % stretch: auto mode must move
  // its reference forward and keep every point.
  StretchSequence s;
  s.frames = 6;
  SequenceOptions o = options(SequenceMode::automatic);
  o.update_zncc = 0.99999;  // noise-free images correlate at ZNCC ≈ 1: ask for a move at the first drop
  const SequenceResult r = test::track(s, o);
  int moved = 0;
  for (const TrackedFrame& f : r.frames) moved += f.reference_frame > 0;
  EXPECT_GT(moved, 0);
  const auto [rms, ok] = test::rms_error(s, r, s.frames);
  EXPECT_EQ(ok, static_cast<int>(r.grid.size())) << r.frames.back().message;
  EXPECT_LT(rms, kTrackingTol);
}

TEST(Sequence, FixedPointFieldsAreTheIncrementBetweenConsecutiveImagesAtTheGridCentres) {
  StretchSequence s;
  s.final_stretch = Vec2(1.2, 1.1);
  s.frames = 2;
  SequenceOptions o = options(SequenceMode::incremental);
  o.fixed_point_fields = true;
  const SequenceResult r = test::track(s, o);
  ASSERT_EQ(r.increments.size(), 2u);
  for (const IncrementField& inc : r.increments) {
    // x ↦ c + (λ_to / λ_from)(x − c) at a fixed pixel x
    const Vec2 ratio = s.stretch(inc.to).cwiseQuotient(s.stretch(inc.from));
    for (std::size_t k = 0; k < r.grid.size(); ++k) {
      ASSERT_EQ(inc.status[k], PointStatus::ok);
      const Vec2 x = r.grid[k].x;
      const Vec2 expected = (ratio - Vec2::Ones()).cwiseProduct(x - s.centre);
      EXPECT_LT((inc.u[k] - expected).norm(), kTrackingTol) << inc.from << "->" << inc.to << " at " << x.transpose();
    }
  }
}

TEST(Sequence, ABlankFrameLosesEveryPointAndTheResultSaysSo) {
  StretchSequence s;
  s.frames = 1;
  const synth::SpecklePattern P = s.pattern();
  const image::Image ref = s.image(P, 0);
  SequenceTracker t(ref, make_grid(s.roi(), s.width, s.height, 31, 10), SequenceOptions{});
  const TrackedFrame& f1 = t.add(image::Image(s.width, s.height, 0.4f, 1.0));
  EXPECT_EQ(f1.ok, 0);
  for (PointStatus st : f1.status) EXPECT_NE(st, PointStatus::ok);
  const TrackedFrame& f2 = t.add(ref);  // incremental: nothing is left to track
  for (PointStatus st : f2.status) EXPECT_EQ(st, PointStatus::lost);
  for (const Vec2& x : f2.x) EXPECT_TRUE(std::isnan(x(0)));
  const SequenceResult& r = t.result();
  EXPECT_EQ(r.termination, SequenceTermination::all_lost);
  EXPECT_NE(r.message.find("every point was lost"), std::string::npos);
}

TEST(Sequence, PointsWithoutTextureInTheReferenceSayWhyInEveryFrame) {
  StretchSequence s;
  s.final_stretch = Vec2(1.05, 1.0);
  s.frames = 1;
  const synth::SpecklePattern P = s.pattern();
  image::Image ref = s.image(P, 0), cur = s.image(P, 1);
  for (image::Image* img : {&ref, &cur})
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < 100; ++x) img->at(x, y) = 0.5f;  // the left part is blank
  SequenceTracker t(ref, make_grid(s.roi(), s.width, s.height, 31, 10), SequenceOptions{});
  t.add(cur);
  const SequenceResult& r = t.result();
  int blank = 0, good = 0;
  for (std::size_t k = 0; k < r.grid.size(); ++k) {
    if (r.grid[k].x(0) + 15 < 100) {
      ++blank;
      EXPECT_EQ(r.frames[0].status[k], PointStatus::no_texture);
      EXPECT_EQ(r.frames[1].status[k], PointStatus::no_texture);
    } else if (r.grid[k].x(0) - 15 > 100) {
      good += r.frames[1].status[k] == PointStatus::ok;
    }
  }
  EXPECT_GT(blank, 0);
  EXPECT_GT(good, 0);
}

TEST(Sequence, TrackSequenceRejectsBadOptionsWithTheirKey) {
  SequenceOptions o;
  o.dic.step = 0;
  try {
    track_sequence({image::Image(50, 50)}, Roi::whole_image(), o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "dic.step");
  }
}

TEST(SequenceMode, NamesAreTheConfigWords) {
  EXPECT_STREQ(to_string(SequenceMode::incremental), "incremental");
  EXPECT_STREQ(to_string(SequenceMode::reference), "reference");
  EXPECT_STREQ(to_string(SequenceMode::automatic), "auto");
}

TEST(Sequence, PositionSigmaStartsAtZeroAndAccumulatesOverIncrements) {
  StretchSequence s;
  s.frames = 4;
  SequenceOptions o = options(SequenceMode::incremental);
  o.fixed_point_fields = true;
  const SequenceResult r = test::track(s, o);
  ASSERT_EQ(r.frames.size(), 5u);
  for (const Vec2& z : r.frames[0].sigma) EXPECT_EQ(z, Vec2::Zero());
  for (std::size_t k = 1; k < r.frames.size(); ++k)
    for (std::size_t p = 0; p < r.grid.size(); ++p) {
      if (r.frames[k].status[p] != PointStatus::ok) continue;
      EXPECT_TRUE(r.frames[k].sigma[p].allFinite());
      // each increment adds its own variance
      EXPECT_GE(r.frames[k].sigma[p](0), r.frames[k - 1].sigma[p](0));
      EXPECT_GE(r.frames[k].sigma[p](1), r.frames[k - 1].sigma[p](1));
    }
  ASSERT_EQ(r.increments.size(), 4u);
  for (std::size_t p = 0; p < r.grid.size(); ++p) {
    if (r.increments[0].status[p] == PointStatus::ok) {
      EXPECT_TRUE(r.increments[0].sigma[p].allFinite());
    }
  }
}

TEST(Sequence, TheReferenceFramesStrainIsExactlyZero) {
  StretchSequence s;
  s.frames = 1;
  const SequenceResult r = test::track(s, options(SequenceMode::incremental));
  int valid = 0;
  for (const StrainPoint& e : r.frames[0].strain) {
    valid += e.valid;
    if (!e.valid) continue;
    EXPECT_EQ(e.exx, 0.0);
    EXPECT_EQ(e.eyy, 0.0);
    EXPECT_EQ(e.exy, 0.0);
    EXPECT_EQ(e.F, Mat2::Identity());
  }
  EXPECT_GT(valid, 0);
}

namespace {

/// Bit for bit, NaN equal to NaN (a lost point's position).
template <class T>
bool same(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

// Streaming (issue 16): keep_frames = false holds only the latest frame, with the same numbers.
TEST(Sequence, WithoutKeptFramesOnlyTheLatestFrameIsHeldAndItIsTheSame) {
  StretchSequence s;
  s.frames = 4;
  SequenceOptions o = options(SequenceMode::incremental);
  o.fixed_point_fields = true;
  const SequenceResult all = test::track(s, o);
  o.keep_frames = false;
  const SequenceResult last = test::track(s, o);
  ASSERT_EQ(last.frames.size(), 1u);
  ASSERT_EQ(last.increments.size(), 1u);
  EXPECT_EQ(last.frames[0].frame, 4);
  EXPECT_TRUE(same(last.frames[0].x, all.frames.back().x));
  EXPECT_TRUE(same(last.increments[0].u, all.increments.back().u));
  EXPECT_EQ(last.message, all.message);
}

// --resume (issue 16): a tracker rebuilt from a checkpoint goes on bit for bit as the one that made it,
// in every mode (auto moves its reference, so the checkpoint's reference frame is neither 0 nor k − 1).
TEST(Sequence, ATrackerResumedFromACheckpointGoesOnExactlyAsTheUninterruptedOne) {
  StretchSequence s;
  s.frames = 5;
  const synth::SpecklePattern P = s.pattern();
  std::vector<image::Image> images;
  for (int k = 0; k <= s.frames; ++k) images.push_back(s.image(P, k));
  for (SequenceMode mode : {SequenceMode::incremental, SequenceMode::reference, SequenceMode::automatic}) {
    SCOPED_TRACE(to_string(mode));
    SequenceOptions o = options(mode);
    o.update_zncc = 0.99999;
    o.fixed_point_fields = true;
    const auto grid = make_grid(s.roi(), s.width, s.height, o.dic.icgn.subset_size, o.dic.step);
    SequenceTracker whole(images[0], grid, o);
    SequenceTracker first(images[0], grid, o);
    std::string checkpoint;
    for (int k = 1; k <= s.frames; ++k) {
      whole.add(images[k]);
      if (k <= 3) first.add(images[k]);
      if (k == 3) checkpoint = first.checkpoint();
    }
    const SequenceResumePoint at = SequenceTracker::resume_point(checkpoint);
    EXPECT_EQ(at.next_frame, 4);
    SequenceTracker resumed(images[at.reference_frame], images[at.next_frame - 1], grid, o, checkpoint);
    for (int k = 4; k <= s.frames; ++k) {
      const TrackedFrame& f = resumed.add(images[k]);
      const TrackedFrame& g = whole.result().frames[k];
      EXPECT_EQ(f.frame, k);
      EXPECT_EQ(f.reference_frame, g.reference_frame);
      EXPECT_TRUE(same(f.x, g.x));
      EXPECT_TRUE(same(f.zncc, g.zncc));
      EXPECT_TRUE(same(f.sigma, g.sigma));
      EXPECT_EQ(f.status, g.status);
      EXPECT_TRUE(same(resumed.result().increments.back().u, whole.result().increments[k - 1].u));
    }
    EXPECT_EQ(resumed.result().message, whole.result().message);
  }
}

TEST(Sequence, ACheckpointOfAnotherGridOrATruncatedOneIsRefusedWithTheResumeKey) {
  StretchSequence s;
  s.frames = 1;
  const synth::SpecklePattern P = s.pattern();
  const image::Image a = s.image(P, 0), b = s.image(P, 1);
  const SequenceOptions o = options(SequenceMode::incremental);
  const auto grid = make_grid(s.roi(), s.width, s.height, o.dic.icgn.subset_size, o.dic.step);
  SequenceTracker t(a, grid, o);
  t.add(b);
  const std::string c = t.checkpoint();
  const auto other = make_grid(s.roi(), s.width, s.height, o.dic.icgn.subset_size, o.dic.step + 2);
  for (const auto& [g, bytes] :
       {std::pair{other, c}, std::pair{grid, c.substr(0, c.size() / 2)}, std::pair{grid, std::string("x")}}) {
    try {
      SequenceTracker r(b, b, g, o, bytes);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("resume"), std::string::npos) << e.what();
    }
  }
}
