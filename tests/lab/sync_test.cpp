#include "tricot/lab/sync.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tricot/core/error.hpp"
#include "tricot/io/log.hpp"
#include "tricot/synth/lab_record.hpp"

using namespace tricot;
using namespace tricot::lab;

namespace {

// The requirement for the recovered clock offset.
constexpr double offset_tolerance_s = 0.010;
// Forces at image times: the RMS error against the truth stays within 1.5× the noise expected from the
// log's noise averaged over the exposure plus the tare's own error (1.5: RMS over ~50 images scatters).
constexpr double noise_margin = 1.5;

// A J-shaped force–grip relation (N, mm): soft at first, then stiffening, as a knit.
double fabric_force(double g) { return 1.5 * g + 0.03 * g * g * g; }

LoadLog log_of(const synth::LabRecord& r) { return {"synthetic.lvm", r.log_time, r.log_force, r.log_crosshead}; }
ImageTimes images_of(const synth::LabRecord& r) { return {r.frame_time, r.grip, {}}; }

// Reads the record back through the LabVIEW text, as the lab's file would be read.
LoadLog log_through_file(const synth::LabRecord& r, const synth::LabRecordOptions& o) {
  const io::LogTable t = io::parse_log(io::to_log_text(synth::labview_log(r, o)), "synthetic.lvm");
  LoadLog log{"synthetic.lvm", t.times("temps"), t.numbers("force"), {}};
  if (t.has_column("traverse")) log.crosshead = t.numbers("traverse");
  return log;
}

std::string error_of(const LoadLog& log, const ImageTimes& images, const SyncOptions& o = {}) {
  try {
    synchronise(log, images, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Sync, CrossheadCorrelationRecoversAnOffsetOf370msWithin10ms) {
  synth::LabRecordOptions o;  // 0.37 s, 2 fps, 100 Hz, 1 % noise
  const auto record = synth::make_lab_record(o, fabric_force);
  const SyncResult r = synchronise(log_through_file(record, o), images_of(record));
  EXPECT_EQ(r.method, SyncMethod::crosshead);
  std::printf("with cross-head: %s\n", r.brief_report().c_str());
  EXPECT_NEAR(r.clock_offset_s, 0.37, offset_tolerance_s) << r.brief_report();
  EXPECT_EQ(r.termination, SyncTermination::found);
  EXPECT_EQ(r.lag_s.size(), r.correlation.size());
  EXPECT_GT(r.peak_correlation, 0.999);
}

TEST(Sync, GripMeasuredWithTheOppositeSignCorrelatesAsWell) {
  synth::LabRecordOptions o;
  const auto record = synth::make_lab_record(o, fabric_force);
  ImageTimes images = images_of(record);
  for (double& g : images.grip) g = -2 * g;  // another sign convention and unit
  const SyncResult r = synchronise(log_of(record), images);
  EXPECT_NEAR(r.clock_offset_s, 0.37, offset_tolerance_s) << r.brief_report();
  EXPECT_LT(r.peak_correlation, -0.999);
}

TEST(Sync, OnsetMatchingRecoversAnOffsetOf370msWithin10msWithoutCrosshead) {
  synth::LabRecordOptions o;
  o.crosshead_column = false;
  const auto record = synth::make_lab_record(o, fabric_force);
  const SyncResult r = synchronise(log_through_file(record, o), images_of(record));
  EXPECT_EQ(r.method, SyncMethod::onset);
  std::printf("without cross-head: %s\n", r.brief_report().c_str());
  EXPECT_NEAR(r.clock_offset_s, 0.37, offset_tolerance_s) << r.brief_report();
}

// Over 40 noise draws: with a cross-head column every offset is within 10 ms; without, the force's
// 1 % noise limits the onset match, whose RMS error stays within 10 ms (the worst draw is reported).
TEST(Sync, OffsetErrorOverFortyNoiseDrawsStaysWithin10ms) {
  for (bool crosshead : {true, false}) {
    double ss = 0, worst = 0;
    const int draws = 40;
    for (int seed = 1; seed <= draws; ++seed) {
      synth::LabRecordOptions o;
      o.seed = std::uint64_t(seed);
      o.crosshead_column = crosshead;
      const auto record = synth::make_lab_record(o, fabric_force);
      const double e = synchronise(log_of(record), images_of(record)).clock_offset_s - 0.37;
      ss += e * e, worst = std::max(worst, std::abs(e));
    }
    const double rms = std::sqrt(ss / draws);
    std::printf("%s: offset error rms %.2f ms, worst %.2f ms over %d draws\n", crosshead ? "crosshead" : "onset",
                1e3 * rms, 1e3 * worst, draws);
    EXPECT_LT(rms, offset_tolerance_s);
    if (crosshead) {
      EXPECT_LT(worst, offset_tolerance_s);
    }
  }
}

TEST(Sync, ForcesAtImageTimesAreWithinTheExpectedNoiseOfTheTruth) {
  synth::LabRecordOptions o;
  const auto record = synth::make_lab_record(o, fabric_force);
  SyncOptions s;
  s.exposure_s = 0.1;
  const SyncResult r = synchronise(log_of(record), images_of(record), s);
  ASSERT_EQ(r.force.size(), record.force_true.size());
  EXPECT_NEAR(r.tare_N, o.tare_N, 4 * record.force_noise_N / std::sqrt(double(r.tare_samples)));
  // exposure of 0.1 s averages ~10 samples of the 100 Hz log; the tare adds its own error
  const double expected = record.force_noise_N * std::sqrt(1.0 / (s.exposure_s * o.log_rate_hz) + 1.0 / r.tare_samples);
  double ss = 0;
  for (std::size_t k = 0; k < r.force.size(); ++k) ss += std::pow(r.force[k] - record.force_true[k], 2);
  const double rms = std::sqrt(ss / double(r.force.size()));
  std::printf("%s; force at %zu images: rms error %.4f N, expected %.4f N (log noise %.4f N)\n",
              r.brief_report().c_str(), r.force.size(), rms, expected, record.force_noise_N);
  EXPECT_LT(rms, noise_margin * expected) << "rms " << rms << " expected " << expected;
  EXPECT_GT(rms, expected / noise_margin) << "rms " << rms << " expected " << expected;
}

TEST(Sync, GivenOffsetAndTareOverrideTheEstimates) {
  synth::LabRecordOptions o;
  o.noise = 0;
  const auto record = synth::make_lab_record(o, fabric_force);
  SyncOptions s;
  s.clock_offset_s = 0.37;
  s.tare_N = 0.8;
  const SyncResult r = synchronise(log_of(record), images_of(record), s);
  EXPECT_EQ(r.method, SyncMethod::given);
  EXPECT_EQ(r.clock_offset_s, 0.37);
  EXPECT_TRUE(r.tare_given);
  for (std::size_t k = 0; k < r.force.size(); ++k) EXPECT_NEAR(r.force[k], record.force_true[k], 1e-6);
  // the cross-head at the images: twice the quarter model's grip (noise 1 µm)
  ASSERT_EQ(r.crosshead.size(), r.force.size());
  for (std::size_t k = 0; k < r.crosshead.size(); ++k) EXPECT_NEAR(0.5 * r.crosshead[k], record.grip_true[k], 5e-3);
}

TEST(Sync, MeanOverIntegratesThePiecewiseLinearForce) {
  const std::vector<double> t{0, 1, 2}, f{0, 2, 0};
  EXPECT_DOUBLE_EQ(mean_over(t, f, 0, 2), 1.0);
  EXPECT_DOUBLE_EQ(mean_over(t, f, 0.5, 1.5), 1.5);  // (∫ over [0.5,1.5]) = 2·(1+2)/2·0.5 = 1.5
  EXPECT_DOUBLE_EQ(mean_over(t, f, 0.25, 0.25), 0.5);
}

TEST(Sync, HingeOnsetFindsTheKinkOfANoiseFreeRamp) {
  std::vector<double> t, y;
  for (int i = 0; i < 300; ++i) t.push_back(0.01 * i), y.push_back(1 + 2 * std::max(0.0, t.back() - 1.234));
  EXPECT_NEAR(hinge_onset(t, y, 1), 1.234, 1e-5);
}

TEST(Sync, LogThatDoesNotCoverEveryImageNamesTheFirstImageLeftOut) {
  synth::LabRecordOptions o;
  o.log_tail_s = 0;
  const auto record = synth::make_lab_record(o, fabric_force);
  ImageTimes images = images_of(record);
  images.names = synth::timed_file_names(images.time);
  SyncOptions s;
  s.clock_offset_s = 0.37 + 0.2;  // the last images then fall beyond the log's end
  const std::string e = error_of(log_of(record), images, s);
  EXPECT_NE(e.find(images.names[images.names.size() - 1]), std::string::npos) << e;
  EXPECT_NE(e.find("does not cover"), std::string::npos) << e;
}

TEST(Sync, StillGripIsAnError) {
  synth::LabRecordOptions o;
  const auto record = synth::make_lab_record(o, fabric_force);
  ImageTimes images = images_of(record);
  std::fill(images.grip.begin(), images.grip.end(), 0.0);
  EXPECT_NE(error_of(log_of(record), images).find("does not move"), std::string::npos);
}

TEST(Sync, TimeGoingBackwardsInTheLogIsAnError) {
  synth::LabRecordOptions o;
  const auto record = synth::make_lab_record(o, fabric_force);
  LoadLog log = log_of(record);
  std::swap(log.time[10], log.time[11]);
  EXPECT_EQ(error_of(log, images_of(record)),
            "synthetic.lvm: log.time: time does not increase at index 11 (got 0.1, expected > 0.11)");
}

TEST(Sync, AnOffsetBeyondTheSearchRangeIsFlagged) {
  synth::LabRecordOptions o;
  o.clock_offset_s = 1.5;
  const auto record = synth::make_lab_record(o, fabric_force);
  SyncOptions s;
  s.max_offset_s = 1.0;
  const SyncResult r = synchronise(log_of(record), images_of(record), s);
  EXPECT_EQ(r.termination, SyncTermination::at_search_limit) << r.brief_report();
}

TEST(Sync, OutOfRangeOptionIsAnError) {
  SyncOptions s;
  s.exposure_s = -1;
  EXPECT_THROW(s.validate(), InputError);
}

TEST(Sync, FrameTimesFromARateAndAStart) {
  EXPECT_EQ(frame_times(3, 2, 1.5), (std::vector<double>{1.5, 2.0, 2.5}));
  EXPECT_THROW(frame_times(3, 0), InputError);
}

TEST(Sync, ForceStepsStartAfterTheReferenceImageAndDivideByTheWidth) {
  const ImageTimes images{{10, 10.5, 11}, {0, 0.1, 0.2}, {}};
  SyncResult sync;
  sync.force = {0, 3, 6};
  const auto steps = force_steps(images, sync, {0, 0.1, 0.2}, 150);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[1].step, 2);
  EXPECT_EQ(steps[1].time_s, 1.0);
  EXPECT_EQ(steps[1].grip_mm, 0.2);
  EXPECT_EQ(steps[1].force_N, 6);
  EXPECT_DOUBLE_EQ(steps[1].force_per_width, 6.0 / 150);
  EXPECT_THROW(force_steps(images, sync, {0, 0.1}, 150), InputError);
  EXPECT_THROW(force_steps(images, sync, {0, 0.1, 0.2}, 0), InputError);
}
