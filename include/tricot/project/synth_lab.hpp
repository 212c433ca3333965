// `tricot synth` raw lab record (issue 11): what a lab would hold for a synthetic test, so that `tricot
// experiment` and `tricot relax` are checked against a known truth. With `[synth.lab] enabled = true`
// (and [synth.images]) each test also gets
//
//   DIR/<test>/lab/load.txt         a LabVIEW-like load-cell log: tab, decimal comma, 10 header lines,
//                                   `Temps [s]`, `Force [N]` (and `Traverse [mm]`), at log_rate_hz, with a
//                                   tare, noise, and its own clock (log = camera + clock_offset_s)
//   DIR/<test>/lab/camera.csv       the camera log: file, time [s] (frame j at j / fps on the camera clock)
//   DIR/<test>/lab/relaxation.txt   a relaxation test's log (Prony series with relaxation_tau_s)
//   DIR/<test>/lab/truth.json       clock offset, tare, noise σ, each frame's true force and grip
//
// The force between frames is interpolated linearly in time between the FE steps the frames show;
// the cross-head (full specimen) is twice the quarter model's grip displacement. The log starts
// log_lead_s before image 0, at rest, and stops log_tail_s after the last image, held.
#pragma once

#include <cstdint>
#include <filesystem>

#include "tricot/core/options.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/log.hpp"
#include "tricot/project/spec.hpp"

namespace tricot::project {

/// `[synth.lab]` as a typed spec: each key declared once in keys() (core/options.hpp).
struct SynthLabSpec {
  bool enabled = false;
  double fps = 2;
  double log_rate_hz = 100;
  double clock_offset_s = 0.37;
  double tare_N = 0.8;
  double noise = 0.01;
  bool crosshead = true;
  double crosshead_noise_mm = 0.001;
  double log_lead_s = 2;
  double log_tail_s = 2;
  bool relaxation = true;
  io::Reals relaxation_tau_s{360};
  io::Reals relaxation_amplitudes_N{10};
  Origin origin{"synth.lab"};

  static auto keys() {
    using O = SynthLabSpec;
    return std::tuple{
        option(&O::enabled, "synth.lab.enabled",
               "Write DIR/<test>/lab/ (load.txt, camera.csv, relaxation.txt, truth.json)."),
        option(&O::fps, "synth.lab.fps", "Camera frame rate, images per second, > 0.", 1e-6, 1e6),
        option(&O::log_rate_hz, "synth.lab.log_rate_hz", "Load-cell sampling rate, Hz, > 0.", 1e-3, 1e6),
        option(&O::clock_offset_s, "synth.lab.clock_offset_s", "Log clock minus camera clock, s."),
        option(&O::tare_N, "synth.lab.tare_N", "Force the load cell reads at rest, N."),
        option(&O::noise, "synth.lab.noise", "σ of the force noise, fraction of the test's peak force, ≥ 0.", 0, 1),
        option(&O::crosshead, "synth.lab.crosshead",
               "The log has a cross-head column (Traverse [mm], twice the quarter's grip)."),
        option(&O::crosshead_noise_mm, "synth.lab.crosshead_noise_mm", "σ of the cross-head reading, mm, ≥ 0.", 0, 1e3),
        option(&O::log_lead_s, "synth.lab.log_lead_s", "The log starts this long before image 0 (at rest), s, ≥ 0.", 0,
               1e6),
        option(&O::log_tail_s, "synth.lab.log_tail_s", "... and stops this long after the last image (held), s, ≥ 0.",
               0, 1e6),
        option(&O::relaxation, "synth.lab.relaxation",
               "Also write relaxation.txt: a relaxation test's log (1 sample/s, 1 h hold)."),
        option(&O::relaxation_tau_s, "synth.lab.relaxation_tau_s", "Its characteristic times, s, > 0 (1 to 3).", 1e-3,
               1e9),
        option(&O::relaxation_amplitudes_N, "synth.lab.relaxation_amplitudes_N",
               "Their amplitudes F_i, N (one per time).")};
  }
  static SynthLabSpec from_config(const io::Node& lab);
};

/// `[synth.lab]`, generated from SynthLabSpec::keys() (defaults: SynthLabSpec's).
io::SectionSpec synth_lab_section();

/// Writes DIR/<test>/lab/ from the test's simulation and the frames of its camera.json (the images must
/// have been written). Noise is drawn from `seed`. Returns the number of log samples written.
int write_lab_record(const SynthLabSpec& lab, const fem::SimulationResult& sim, const std::filesystem::path& test_dir,
                     std::uint64_t seed, const Log& log);

}  // namespace tricot::project
