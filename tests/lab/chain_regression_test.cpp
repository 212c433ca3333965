// The lab chain on rendered images (issue 11): a uniaxial pull seen by a 2 fps camera and logged by a
// 100 Hz load cell with its own clock. The images go through the DIC sequence, the field is folded
// into the quarter model, the grip's motion is estimated from it, and the load cell is synchronised
// with it, with and without the log's cross-head column.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tricot/dic/grid.hpp"
#include "tricot/dic/sequence.hpp"
#include "tricot/lab/specimen.hpp"
#include "tricot/lab/sync.hpp"
#include "tricot/synth/lab_record.hpp"
#include "tricot/synth/speckle.hpp"

using namespace tricot;

namespace {

// The requirement for the recovered clock offset.
constexpr double offset_tolerance_s = 0.010;
// Camera noise, fraction of full scale.
constexpr double image_noise = 0.01;
// Grip displacement from the field: DIC's random error (~0.01 px = 2.5 µm per point at 1 % noise,
// accumulated over 36 increments and averaged over 88 points) extrapolated to the grip.
constexpr double grip_tolerance_mm = 0.01;
// The field's σ (IC-GN's, accumulated over 36 increments) against its actual RMS error over 176
// values: their sampling error is ~5 %, and consecutive increments share an image, which the
// accumulation treats as independent.
constexpr double sigma_ratio_tolerance = 0.35;

double fabric_force(double g) { return 1.5 * g + 0.03 * g * g * g; }

}  // namespace

TEST(LabChain, ImagesThroughDicGiveTheGripMotionThatSynchronisesTheLoadCell) {
  synth::LabRecordOptions o;
  o.crosshead_travel_mm = 10;  // grip 5 mm on a 50 mm free length: 20 % stretch
  const synth::LabRecord record = synth::make_lab_record(o, fabric_force);

  // Camera: 240 px square, 0.25 mm/px, the specimen centre at the image centre, Y up.
  const int size = 240;
  dic::PhysicalFrame frame;
  frame.mm_per_px = 0.25;
  frame.centre_px = {0.5 * (size - 1), 0.5 * (size - 1)};
  const lab::SpecimenGeometry geometry{40, 50, 0};
  synth::SpeckleOptions speckle;
  speckle.subsamples = 2;
  const synth::SpecklePattern pattern(speckle, -10, -10, size + 10, size + 10);
  std::uint64_t noise_seed = 10;
  auto image = [&](double grip) {
    const double ly = 1 + grip / geometry.half_length(), lx = 1 / std::sqrt(ly);  // uniaxial, isochoric
    const Vec2 c = frame.centre_px;
    const image::Image clean = synth::render(
        pattern, size, size, [&](const Vec2& x) { return Vec2(c(0) + (x(0) - c(0)) / lx, c(1) + (x(1) - c(1)) / ly); });
    return synth::add_noise(clean, image_noise, ++noise_seed);
  };
  dic::SequenceOptions so;
  so.dic.step = 15;
  const auto roi = dic::Roi::rectangle(60, 40, size - 61, size - 41);
  dic::SequenceTracker tracker(image(record.grip_true[0]),
                               dic::make_grid(roi, size, size, so.dic.icgn.subset_size, so.dic.step), so);
  for (std::size_t k = 1; k < record.frame_time.size(); ++k) tracker.add(image(record.grip_true[k]));
  const dic::SequenceResult& seq = tracker.result();

  const lab::QuarterField field = lab::fold_sequence(seq, frame, geometry, lab::FieldKind::cumulative);
  std::printf("%s\n", field.report.c_str());
  EXPECT_EQ(field.outside + field.incomplete, 0);
  std::vector<double> grip{0.0};
  for (double g : lab::grip_from_field(field, geometry)) grip.push_back(g);
  double worst = 0;
  for (std::size_t k = 0; k < grip.size(); ++k) worst = std::max(worst, std::abs(grip[k] - record.grip_true[k]));
  std::printf("grip from the field: worst error %.5f mm over %zu images\n", worst, grip.size());
  EXPECT_LT(worst, grip_tolerance_mm);

  // The field's σ against its actual error at the last image (truth: v = (λy − 1)·Y, u = (λx − 1)·X).
  {
    const Eigen::Index last = field.v.rows() - 1;
    const double ly = 1 + record.grip_true.back() / geometry.half_length(), lx = 1 / std::sqrt(ly);
    double e2 = 0, s2 = 0;
    for (std::size_t a = 0; a < field.X.size(); ++a) {
      const Eigen::Index i = Eigen::Index(a);
      e2 += std::pow(field.u(last, i) - (lx - 1) * field.X[a](0), 2) +
            std::pow(field.v(last, i) - (ly - 1) * field.X[a](1), 2);
      s2 += std::pow(field.sigma_u(last, i), 2) + std::pow(field.sigma_v(last, i), 2);
    }
    const double rms_error = std::sqrt(e2 / (2.0 * field.X.size())), rms_sigma = std::sqrt(s2 / (2.0 * field.X.size()));
    std::printf("field at the last image: rms error %.5f mm, rms sigma %.5f mm\n", rms_error, rms_sigma);
    EXPECT_NEAR(rms_error / rms_sigma, 1.0, sigma_ratio_tolerance);
  }

  const lab::ImageTimes images{record.frame_time, grip, {}};
  const lab::SyncResult with =
      lab::synchronise({"log", record.log_time, record.log_force, record.log_crosshead}, images);
  const lab::SyncResult without = lab::synchronise({"log", record.log_time, record.log_force, {}}, images);
  std::printf("with cross-head: %s\nwithout: %s\n", with.brief_report().c_str(), without.brief_report().c_str());
  EXPECT_NEAR(with.clock_offset_s, o.clock_offset_s, offset_tolerance_s);
  EXPECT_NEAR(without.clock_offset_s, o.clock_offset_s, offset_tolerance_s);
}
