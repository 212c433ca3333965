// `tricot synth` raw lab record (see synth_lab.hpp).
#include "tricot/project/synth_lab.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "tricot/io/files.hpp"
#include "tricot/io/log.hpp"
#include "tricot/project/synth_images.hpp"
#include "tricot/synth/lab_record.hpp"

#include "spec/schema.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

io::SectionSpec synth_lab_section() {
  io::SectionSpec s{
      "lab",
      "The raw lab record of each test (needs [synth.images]): a load-cell log, a camera log, a relaxation log.",
      false,
      {},
      {}};
  add_keys(s, SynthLabSpec{});
  return s;
}

SynthLabSpec SynthLabSpec::from_config(const io::Node& lab) { return read_table<SynthLabSpec>(lab); }

int write_lab_record(const SynthLabSpec& lab, const fem::SimulationResult& sim, const fs::path& test_dir,
                     std::uint64_t seed, const Log& log) {
  const CameraFile cam = read_camera(test_dir / kImagesFolder);
  const double fps = lab.fps, rate = lab.log_rate_hz, delta = lab.clock_offset_s;
  const double lead = lab.log_lead_s, tail = lab.log_tail_s, tare = lab.tare_N;
  // Frames: camera time, true force and grip (quarter model) from the FE step each one shows.
  const std::size_t n = cam.frames.size();
  std::vector<double> tc(n), force(n), grip(n);
  const double c0 = lead - delta;  // camera time of image 0: its log time is `lead`
  double peak = 0;
  for (std::size_t j = 0; j < n; ++j) {
    tc[j] = c0 + double(j) / fps;
    // A rig's setting and hold frames: the guide moves (or holds) with the grip at rest, and the
    // knit's shrinkage loads the cell; the cross-head starts at the last of them (set, hold, pull).
    const CameraFile::Frame& f = cam.frames[j];
    if (f.step > 0) {
      const fem::StepResult& s = sim.steps.at(std::size_t(f.step - 1));
      force[j] = s.edge_force, grip[j] = s.edge_displacement;
    } else if (f.setting > 0) {
      force[j] = sim.setting.at(std::size_t(f.setting - 1)).edge_force;
    }
    peak = std::max(peak, std::abs(force[j]));
  }
  const auto at = [&](const std::vector<double>& y, double camera_t) {
    if (camera_t <= tc.front()) return y.front();
    if (camera_t >= tc.back()) return y.back();
    const std::size_t k = std::size_t(std::upper_bound(tc.begin(), tc.end(), camera_t) - tc.begin());
    const double w = (camera_t - tc[k - 1]) / (tc[k] - tc[k - 1]);
    return (1 - w) * y[k - 1] + w * y[k];
  };
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double sigma_f = lab.noise * peak, sigma_c = lab.crosshead_noise_mm;
  const double duration = lead + double(n - 1) / fps + tail;
  const int samples = static_cast<int>(std::floor(duration * rate)) + 1;
  io::LogWriter w;
  w.metadata = {"LabVIEW Measurement",    "Writer_Version\t2",
                "Reader_Version\t2",      "Separator\tTab",
                "Decimal_Separator\t,",   "Multi_Headings\tNo",
                "X_Columns\tOne",         "Time_Pref\tRelative",
                "Operator\ttricot synth", fmt::format("Date\tsynthetic; sample rate {:g} Hz", rate)};
  w.columns = {"Temps [s]", "Force [N]"};
  const bool crosshead = lab.crosshead;
  if (crosshead) w.columns.push_back("Traverse [mm]");
  w.columns_data.resize(w.columns.size());
  w.digits = 8;
  for (int i = 0; i < samples; ++i) {
    const double tl = double(i) / rate, camera_t = tl - delta;
    w.columns_data[0].push_back(tl);
    w.columns_data[1].push_back(at(force, camera_t) + tare + sigma_f * gauss(rng));
    if (crosshead) w.columns_data[2].push_back(2 * at(grip, camera_t) + sigma_c * gauss(rng));
  }
  const fs::path dir = test_dir / "lab";
  fs::create_directories(dir);
  io::write_atomic(dir / "load.txt", io::to_log_text(w));
  std::vector<io::FrameTime> frames;
  for (std::size_t j = 0; j < n; ++j) frames.push_back({cam.frames[j].file, tc[j]});
  io::write_atomic(dir / "camera.csv", io::to_camera_log_text(frames));

  nlohmann::ordered_json truth = {{"clock_offset_s", delta},
                                  {"tare_N", tare},
                                  {"force_noise_N", sigma_f},
                                  {"crosshead_noise_mm", sigma_c},
                                  {"fps", fps},
                                  {"log_rate_hz", rate},
                                  {"frame_time_s", tc},
                                  {"force_N", force},
                                  {"grip_mm", grip},
                                  {"setting_frames", cam.setting_frames()},
                                  {"hold_frames", cam.hold_frames()}};
  if (lab.relaxation) {
    synth::RelaxationRecordOptions r;
    r.rate_hz = 1;
    r.tau_s = lab.relaxation_tau_s;
    r.amplitudes_N = lab.relaxation_amplitudes_N;
    if (r.tau_s.size() != r.amplitudes_N.size())
      lab.origin.fail("relaxation_amplitudes_N", "one amplitude per relaxation time",
                      std::to_string(r.amplitudes_N.size()), std::to_string(r.tau_s.size()));
    r.seed = seed + 1000;
    const synth::RelaxationRecord rec = synth::make_relaxation_record(r);
    io::write_atomic(dir / "relaxation.txt", io::to_log_text(synth::labview_log(rec)));
    truth["relaxation"] = {{"tau_s", r.tau_s},   {"amplitudes_N", r.amplitudes_N}, {"relaxed_N", r.relaxed_force_N},
                           {"tare_N", r.tare_N}, {"noise_N", r.noise_N},           {"hold_start_s", rec.hold_start_s}};
  }
  io::write_atomic(dir / "truth.json", truth.dump(2) + "\n");
  log.print(fmt::format(
      "  lab record: {} log samples at {:g} Hz (offset {:g} s, tare {:g} N, σ {:.3g} N), {} frames at {:g} fps in {}",
      samples, rate, delta, tare, sigma_f, n, fps, (dir / "").string()));
  return samples;
}

}  // namespace tricot::project
