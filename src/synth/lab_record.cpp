#include "tricot/synth/lab_record.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "tricot/core/error.hpp"

namespace tricot::synth {

namespace {

void check(bool ok, const char* key, double v, const char* expected) {
  if (!ok) throw InputError({"", 0, key}, "out of range", format_number(v), expected);
}

/// The 10 metadata lines a LabVIEW "Write To Measurement File" puts above its data (simplified).
std::vector<std::string> labview_header(const std::string& what, double rate_hz) {
  return {"LabVIEW Measurement",  "Writer_Version\t2",
          "Reader_Version\t2",    "Separator\tTab",
          "Decimal_Separator\t,", "Multi_Headings\tNo",
          "Date\t2026/11/23",     "Time\t14:02:11,5",
          "Description\t" + what, fmt::format("Sample rate (Hz)\t{}", rate_hz)};
}

}  // namespace

void LabRecordOptions::validate() const {
  check(log_rate_hz > 0 && std::isfinite(log_rate_hz), "lab.log_rate_hz", log_rate_hz, "> 0 Hz");
  check(camera_fps > 0 && std::isfinite(camera_fps), "lab.camera_fps", camera_fps, "> 0 images/s");
  check(std::isfinite(clock_offset_s), "lab.clock_offset_s", clock_offset_s, "a finite number of seconds");
  check(std::isfinite(tare_N), "lab.tare_N", tare_N, "a finite force");
  check(noise >= 0 && std::isfinite(noise), "lab.noise", noise, "≥ 0");
  check(crosshead_noise_mm >= 0, "lab.crosshead_noise_mm", crosshead_noise_mm, "≥ 0 mm");
  check(grip_noise_mm >= 0, "lab.grip_noise_mm", grip_noise_mm, "≥ 0 mm");
  check(crosshead_travel_mm > 0, "lab.crosshead_travel_mm", crosshead_travel_mm, "> 0 mm");
  check(rest_s >= 0, "lab.rest_s", rest_s, "≥ 0 s");
  check(ramp_s > 0, "lab.ramp_s", ramp_s, "> 0 s");
  check(hold_s >= 0, "lab.hold_s", hold_s, "≥ 0 s");
  check(log_lead_s >= 0, "lab.log_lead_s", log_lead_s, "≥ 0 s");
  check(log_tail_s >= 0, "lab.log_tail_s", log_tail_s, "≥ 0 s");
}

LabRecord make_lab_record(const LabRecordOptions& o, const std::function<double(double)>& force_of_grip) {
  o.validate();
  LabRecord r;
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> normal(0, 1);
  const double first_image = o.log_lead_s;      // log time
  const double onset = first_image + o.rest_s;  // log time
  const double test_end = onset + o.ramp_s + o.hold_s;
  auto crosshead = [&](double s) { return o.crosshead_travel_mm * std::clamp((s - onset) / o.ramp_s, 0.0, 1.0); };
  double peak = 0;
  for (int i = 0; i <= 100; ++i) peak = std::max(peak, std::abs(force_of_grip(0.5 * o.crosshead_travel_mm * i / 100)));
  r.force_noise_N = o.noise * peak;

  const int frames = static_cast<int>(std::floor((test_end - first_image) * o.camera_fps + 1e-9)) + 1;
  for (int k = 0; k < frames; ++k) {
    const double s = first_image + k / o.camera_fps;  // log time of the image
    r.frame_time.push_back(s - o.clock_offset_s);
    r.grip_true.push_back(0.5 * crosshead(s));
    r.grip.push_back(r.grip_true.back() + o.grip_noise_mm * normal(rng));
    r.force_true.push_back(force_of_grip(r.grip_true.back()));
  }
  const double last_image = first_image + (frames - 1) / o.camera_fps;
  const long samples = std::lround((last_image + o.log_tail_s) * o.log_rate_hz) + 1;
  for (long i = 0; i < samples; ++i) {
    const double s = double(i) / o.log_rate_hz;
    r.log_time.push_back(s);
    const double c = crosshead(s);
    r.log_force.push_back(force_of_grip(0.5 * c) + o.tare_N + r.force_noise_N * normal(rng));
    if (o.crosshead_column) r.log_crosshead.push_back(c + o.crosshead_noise_mm * normal(rng));
  }
  return r;
}

io::LogWriter labview_log(const LabRecord& r, const LabRecordOptions& o) {
  io::LogWriter w;
  w.metadata = labview_header("tensile test, load cell 500 N", o.log_rate_hz);
  w.columns = {"Temps [s]", "Force [N]"};
  w.columns_data = {r.log_time, r.log_force};
  if (!r.log_crosshead.empty()) {
    w.columns.push_back("Traverse [mm]");
    w.columns_data.push_back(r.log_crosshead);
  }
  w.digits = 8;
  return w;
}

void RelaxationRecordOptions::validate() const {
  check(rate_hz > 0 && std::isfinite(rate_hz), "relaxation.rate_hz", rate_hz, "> 0 Hz");
  check(rest_s >= 0, "relaxation.rest_s", rest_s, "≥ 0 s");
  check(ramp_s > 0, "relaxation.ramp_s", ramp_s, "> 0 s");
  check(hold_s > 0, "relaxation.hold_s", hold_s, "> 0 s");
  check(crosshead_mm > 0, "relaxation.crosshead_mm", crosshead_mm, "> 0 mm");
  check(std::isfinite(relaxed_force_N), "relaxation.relaxed_force_N", relaxed_force_N, "a finite force");
  if (amplitudes_N.size() != tau_s.size())
    throw InputError({"", 0, "relaxation.tau_s"}, "one time per amplitude", std::to_string(tau_s.size()),
                     std::to_string(amplitudes_N.size()));
  for (double t : tau_s) check(t > 0 && std::isfinite(t), "relaxation.tau_s", t, "> 0 s");
  check(noise_N >= 0, "relaxation.noise_N", noise_N, "≥ 0 N");
}

RelaxationRecord make_relaxation_record(const RelaxationRecordOptions& o) {
  o.validate();
  RelaxationRecord r;
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> normal(0, 1);
  r.hold_start_s = o.rest_s + o.ramp_s;
  double peak = o.relaxed_force_N;
  for (double a : o.amplitudes_N) peak += a;
  const long samples = std::lround((r.hold_start_s + o.hold_s) * o.rate_hz) + 1;
  for (long i = 0; i < samples; ++i) {
    const double s = double(i) / o.rate_hz;
    const double ramp = std::clamp((s - o.rest_s) / o.ramp_s, 0.0, 1.0);
    double f = peak * ramp;
    if (s > r.hold_start_s) {
      f = o.relaxed_force_N;
      for (std::size_t j = 0; j < o.tau_s.size(); ++j)
        f += o.amplitudes_N[j] * std::exp(-(s - r.hold_start_s) / o.tau_s[j]);
    }
    r.time.push_back(s);
    r.force.push_back(f + o.tare_N + o.noise_N * normal(rng));
    r.crosshead.push_back(o.crosshead_mm * ramp);
  }
  return r;
}

io::LogWriter labview_log(const RelaxationRecord& r) {
  io::LogWriter w;
  const double rate = r.time.size() > 1 ? 1 / (r.time[1] - r.time[0]) : 1;
  w.metadata = labview_header("relaxation test, load cell 500 N", std::round(rate * 1000) / 1000);
  w.columns = {"Temps [s]", "Force [N]", "Traverse [mm]"};
  w.columns_data = {r.time, r.force, r.crosshead};
  w.digits = 8;
  return w;
}

std::vector<std::string> timed_file_names(const std::vector<double>& times, const std::string& prefix,
                                          const std::string& extension) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < times.size(); ++k)
    names.push_back(fmt::format("{}_{:04d}_t{:.3f}s{}", prefix, k, times[k], extension));
  return names;
}

}  // namespace tricot::synth
