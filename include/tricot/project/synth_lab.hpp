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

#include "tricot/fem/solver.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/log.hpp"

namespace tricot::project {

/// `[synth.lab]`: enabled, fps, log_rate_hz, clock_offset_s, tare_N, noise, crosshead, crosshead_noise_mm,
/// log_lead_s, log_tail_s, relaxation, relaxation_tau_s, relaxation_amplitudes_N.
io::SectionSpec synth_lab_section();

/// Writes DIR/<test>/lab/ from the test's simulation and the frames of its camera.json (the images must
/// have been written). Noise is drawn from `seed`. Returns the number of log samples written.
int write_lab_record(const io::Node& lab, const fem::SimulationResult& sim, const std::filesystem::path& test_dir,
                     std::uint64_t seed, const Log& log);

}  // namespace tricot::project
