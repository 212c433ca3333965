#include "tricot/synth/lab_record.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tricot/core/error.hpp"
#include "tricot/io/log.hpp"

using namespace tricot;
using namespace tricot::synth;

namespace {
// Times are written with a 1 µs (camera log) or 1 ms (file names) resolution.
constexpr double file_name_resolution = 5e-4;
double linear(double g) { return 2 * g; }
}  // namespace

TEST(LabRecord, ImagesAndLogFollowTheRequestedClocksAndRates) {
  LabRecordOptions o;
  o.noise = 0;
  o.grip_noise_mm = 0;
  o.crosshead_noise_mm = 0;
  const LabRecord r = make_lab_record(o, linear);
  // images: 2 fps over rest + ramp + hold, the first one log_lead_s after the log starts
  EXPECT_EQ(r.frame_time.size(), std::size_t((o.rest_s + o.ramp_s + o.hold_s) * o.camera_fps) + 1);
  EXPECT_NEAR(r.frame_time[0], o.log_lead_s - o.clock_offset_s, 1e-12);
  EXPECT_NEAR(r.frame_time[1] - r.frame_time[0], 1 / o.camera_fps, 1e-12);
  // log: 100 Hz, from 0 to log_tail_s after the last image (log clock = camera clock + δ)
  EXPECT_NEAR(r.log_time[1], 0.01, 1e-12);
  EXPECT_NEAR(r.log_time.back(), r.frame_time.back() + o.clock_offset_s + o.log_tail_s, 1e-9);
  // tare at rest, the grip is half the cross-head, the force follows the grip
  EXPECT_NEAR(r.log_force[0], o.tare_N, 1e-12);
  EXPECT_NEAR(r.grip_true.back(), 0.5 * o.crosshead_travel_mm, 1e-12);
  EXPECT_NEAR(r.force_true.back(), linear(0.5 * o.crosshead_travel_mm), 1e-12);
  EXPECT_NEAR(r.log_crosshead.back(), o.crosshead_travel_mm, 1e-12);
}

TEST(LabRecord, NoiseHasTheRequestedSizeAtRest) {
  LabRecordOptions o;  // 1 % of the peak force
  const LabRecord r = make_lab_record(o, linear);
  EXPECT_NEAR(r.force_noise_N, 0.01 * linear(0.5 * o.crosshead_travel_mm), 1e-12);
  double s = 0, s2 = 0;
  const int n = int(o.log_rate_hz * (o.log_lead_s + o.rest_s)) - 1;
  for (int i = 0; i < n; ++i) s += r.log_force[i] - o.tare_N, s2 += std::pow(r.log_force[i] - o.tare_N, 2);
  EXPECT_NEAR(std::sqrt(s2 / n), r.force_noise_N, 0.15 * r.force_noise_N);  // 500 samples: ±~3 % (1σ)
}

TEST(LabRecord, LabviewFileHasATenLineHeaderAndDecimalCommas) {
  LabRecordOptions o;
  const LabRecord r = make_lab_record(o, linear);
  const std::string text = io::to_log_text(labview_log(r, o));
  const io::LogTable t = io::parse_log(text, "lab.lvm");
  EXPECT_EQ(t.metadata.size(), 10u);
  EXPECT_EQ(t.format.delimiter, '\t');
  EXPECT_TRUE(t.format.decimal_comma);
  EXPECT_EQ(t.rows(), r.log_time.size());
  EXPECT_NEAR(t.numbers("Force [N]")[123], r.log_force[123], 1e-6);
  EXPECT_NEAR(t.numbers("traverse")[1500], r.log_crosshead[1500], 1e-6);
}

TEST(LabRecord, TimedFileNamesAndCameraLogReadBackTheTimes) {
  const std::vector<double> t{1.63, 2.13, 2.63};
  const auto names = timed_file_names(t);
  EXPECT_EQ(names[1], "img_0001_t2.130s.tif");
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(io::time_from_file_name(names[k]), t[k], file_name_resolution);
  std::vector<io::FrameTime> frames;
  for (std::size_t k = 0; k < t.size(); ++k) frames.push_back({names[k], t[k]});
  const io::LogTable c = io::parse_log(io::to_camera_log_text(frames), "camera.csv");
  EXPECT_EQ(c.text("file"), names);
  EXPECT_EQ(c.times("time"), t);
}

TEST(RelaxationRecord, HoldsAndRelaxesAsThePronySeries) {
  RelaxationRecordOptions o;
  o.noise_N = 0;
  const RelaxationRecord r = make_relaxation_record(o);
  EXPECT_NEAR(r.hold_start_s, o.rest_s + o.ramp_s, 1e-12);
  const std::size_t i = std::size_t((r.hold_start_s + 360) * o.rate_hz);
  EXPECT_NEAR(r.force[i], o.tare_N + 20 + 10 * std::exp(-1.0), 1e-9);
  EXPECT_NEAR(r.crosshead[i], o.crosshead_mm, 1e-12);
}

TEST(LabRecord, OutOfRangeOptionNamesItsKey) {
  LabRecordOptions o;
  o.camera_fps = 0;
  try {
    o.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "lab.camera_fps");
  }
}
