#include "tricot/lab/relaxation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tricot/core/error.hpp"
#include "tricot/io/log.hpp"
#include "tricot/synth/lab_record.hpp"

using namespace tricot;
using namespace tricot::lab;

namespace {

// The requirement on the characteristic time.
constexpr double tau_tolerance = 0.02;
// F∞/F0 from a 0.3 N-noise record of 30 N: the ratio is fitted from ~7000 samples.
constexpr double ratio_tolerance = 0.005;

RelaxationResult fit(const synth::RelaxationRecord& r, const RelaxationOptions& o = {}) {
  return fit_relaxation(r.time, r.force, r.crosshead, o, "relax.lvm");
}

}  // namespace

TEST(Relaxation, RecoversTau360sWithin2PercentFromANoisyRecord) {
  synth::RelaxationRecordOptions o;  // τ = 360 s, F∞ = 20 N, F1 = 10 N, 2 Hz, 1 h hold
  o.noise_N = 0.3;                   // 1 % of the peak force
  const auto record = synth::make_relaxation_record(o);
  // read back through the LabVIEW text, as the lab's file would be read
  const io::LogTable t = io::parse_log(io::to_log_text(synth::labview_log(record)), "relax.lvm");
  const RelaxationResult r =
      fit_relaxation(t.times("temps"), t.numbers("force"), t.numbers("traverse"), {}, "relax.lvm");
  EXPECT_EQ(r.termination, RelaxationTermination::converged);
  ASSERT_EQ(r.chosen_terms, 1) << r.brief_report();
  EXPECT_NEAR(r.best().terms[0].tau_s / 360.0, 1.0, tau_tolerance) << r.brief_report();
  EXPECT_NEAR(r.best().relaxed_ratio(), 20.0 / 30.0, ratio_tolerance);
  std::printf("%s\n", r.brief_report().c_str());
  EXPECT_NEAR(r.tare_N, o.tare_N, 0.1);
  EXPECT_NEAR(r.hold_start_s, record.hold_start_s, 0.5);
}

TEST(Relaxation, TellsATwoTermRecordFromAOneTermOne) {
  synth::RelaxationRecordOptions o;
  o.noise_N = 0.3;
  o.amplitudes_N = {6, 10};
  o.tau_s = {30, 360};
  const RelaxationResult two = fit(synth::make_relaxation_record(o));
  std::printf("two-term record: %s\n", two.brief_report().c_str());
  ASSERT_EQ(two.chosen_terms, 2) << two.brief_report();
  EXPECT_NEAR(two.best().terms[0].tau_s / 30.0, 1.0, 0.1) << two.brief_report();
  EXPECT_NEAR(two.best().terms[1].tau_s / 360.0, 1.0, 0.05) << two.brief_report();
  EXPECT_LT(two.fits[1].bic, two.fits[0].bic);

  o.amplitudes_N = {10};
  o.tau_s = {360};
  const RelaxationResult one = fit(synth::make_relaxation_record(o));
  std::printf("one-term record: %s\n", one.brief_report().c_str());
  EXPECT_EQ(one.chosen_terms, 1) << one.brief_report();
}

TEST(Relaxation, WithoutCrossheadTheHoldStartsAtThePeakForce) {
  synth::RelaxationRecordOptions o;
  const auto record = synth::make_relaxation_record(o);
  RelaxationOptions ro;
  ro.tare_N = o.tare_N;
  const RelaxationResult r = fit_relaxation(record.time, record.force, {}, ro);
  EXPECT_NEAR(r.hold_start_s, record.hold_start_s, 2.0);
  EXPECT_NEAR(r.best().terms[0].tau_s / 360.0, 1.0, tau_tolerance);
}

TEST(Relaxation, QuasiStaticMatchesTheClosedFormExcess) {
  PronyFit f;
  f.relaxed_N = 20;
  f.terms = {{10, 360}};
  const QuasiStatic slow = quasi_static(f, 3600, 0.05);
  EXPECT_NEAR(slow.viscous_excess, 0.5 * 0.1 * (1 - std::exp(-10.0)), 1e-12);
  EXPECT_TRUE(slow.quasi_static);
  const QuasiStatic fast = quasi_static(f, 60, 0.05);
  EXPECT_NEAR(fast.viscous_excess, 0.5 * 6 * (1 - std::exp(-1.0 / 6)), 1e-12);
  EXPECT_FALSE(fast.quasi_static);
  // the shortest quasi-static duration solves 0.5 (360/T)(1 − e^(−T/360)) = 0.05
  const double T = fast.min_duration_s;
  EXPECT_NEAR(0.5 * (360 / T) * (1 - std::exp(-T / 360)), 0.05, 1e-9);
}

TEST(Relaxation, TooShortAHoldIsAnError) {
  const std::vector<double> t{0, 1, 2, 3, 4, 5}, f{0, 1, 2, 2, 2, 2}, c{0, 1, 2, 2, 2, 2};
  EXPECT_THROW(fit_relaxation(t, f, c), InputError);
}

TEST(Relaxation, TimeGoingBackwardsIsAnError) {
  std::vector<double> t(20), f(20, 1.0), c(20, 1.0);
  for (int i = 0; i < 20; ++i) t[i] = i;
  t[7] = 3;
  EXPECT_THROW(fit_relaxation(t, f, c), InputError);
}
