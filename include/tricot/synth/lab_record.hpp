// A raw lab record with a known truth (issue 11, docs/theory.md §1): what a load cell's acquisition and a
// camera would have written during a tensile test, with the imperfections the synchronisation must
// undo — a clock offset, a tare, noise, a log that starts before the images and stops after them —
// and a relaxation test's log. The values are made here; io::to_log_text writes them the way a
// LabVIEW acquisition on a French PC does (tab, decimal comma, a 10-line metadata header).
//
// Clocks: the log's zero is its first sample. An image taken at log time s has camera time s − δ,
// δ = clock_offset_s. The cross-head is at rest for `rest_s` after the first image, moves at constant
// speed for `ramp_s`, then holds for `hold_s` while the images go on. The grip displacement of the
// quarter model is half the cross-head travel (docs/theory.md §6: symmetry on y = 0).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tricot/io/log.hpp"

namespace tricot::synth {

struct LabRecordOptions {
  double log_rate_hz = 100;           ///< load-cell sampling rate, > 0
  double camera_fps = 2;              ///< images per second, > 0
  double clock_offset_s = 0.37;       ///< δ = log clock − camera clock, s
  double tare_N = 0.8;                ///< force the cell reads at rest, N
  double noise = 0.01;                ///< σ of the force noise, fraction of the test's peak force, ≥ 0
  double crosshead_noise_mm = 0.001;  ///< σ of the cross-head reading, mm, ≥ 0
  double grip_noise_mm = 0.002;       ///< σ of the grip displacement DIC measures, mm, ≥ 0
  double crosshead_travel_mm = 20;    ///< cross-head travel of the ramp, mm, > 0
  double rest_s = 3;                  ///< rest after the first image, s, ≥ 0
  double ramp_s = 12;  ///< duration of the constant-speed ramp, s, > 0 (24 images at 2 fps: the paper has 21–28 steps)
  double hold_s = 3;   ///< hold after the ramp, images still taken, s, ≥ 0
  double log_lead_s = 2;         ///< the log starts this long before the first image, s, ≥ 0
  double log_tail_s = 2;         ///< ... and stops this long after the last, s, ≥ 0
  bool crosshead_column = true;  ///< the log has a cross-head column
  std::uint64_t seed = 1;        ///< random seed of every noise

  /// Throws InputError naming `lab.<field>` when out of range.
  void validate() const;
};

struct LabRecord {
  // The images (camera clock).
  std::vector<double> frame_time;  ///< s
  std::vector<double> grip;        ///< grip displacement DIC would measure (truth + noise), mm
  std::vector<double> grip_true;   ///< mm
  std::vector<double> force_true;  ///< full-specimen force at each image instant, no tare, no noise, N
  // The load-cell log (log clock).
  std::vector<double> log_time;       ///< s, from 0
  std::vector<double> log_force;      ///< N, with tare and noise
  std::vector<double> log_crosshead;  ///< mm, with noise; empty without the column
  double force_noise_N = 0;           ///< σ of the force noise that was added
};

/// Makes the record of a test whose full-specimen force is `force_of_grip(grip displacement, mm)` (N),
/// with force_of_grip(0) = 0 (any tare is added here). Validates the options.
LabRecord make_lab_record(const LabRecordOptions& options, const std::function<double(double)>& force_of_grip);

/// The record's log as a LabVIEW acquisition writes it: 10 metadata lines, then `Temps [s]`,
/// `Force [N]` (and `Traverse [mm]`), tab-separated with decimal commas and CRLF.
io::LogWriter labview_log(const LabRecord& record, const LabRecordOptions& options);

/// A relaxation test (paper §3.1.1): a ramp to a held displacement, then the force relaxes as a
/// Prony series F(t) = F∞ + Σ_i F_i exp(−(t − t_hold)/τ_i) while the cross-head holds.
struct RelaxationRecordOptions {
  double rate_hz = 2;                    ///< sampling rate, > 0
  double rest_s = 5;                     ///< at rest before the ramp, s, ≥ 0
  double ramp_s = 10;                    ///< ramp to the held displacement, s, > 0
  double hold_s = 3600;                  ///< hold, s, > 0
  double crosshead_mm = 30;              ///< held cross-head position, mm, > 0
  double relaxed_force_N = 20;           ///< F∞, N
  std::vector<double> amplitudes_N{10};  ///< F_i, N, one per term
  std::vector<double> tau_s{360};        ///< τ_i, s, > 0, one per term
  double tare_N = 0.5;                   ///< N
  double noise_N = 0.1;                  ///< σ of the force noise, N, ≥ 0
  std::uint64_t seed = 1;

  void validate() const;  ///< InputError naming `relaxation.<field>`
};
struct RelaxationRecord {
  std::vector<double> time, force, crosshead;  ///< the log: s from 0, N with tare and noise, mm
  double hold_start_s = 0;                     ///< when the hold begins (truth)
};
RelaxationRecord make_relaxation_record(const RelaxationRecordOptions& options);
/// The relaxation log as a LabVIEW file (as labview_log).
io::LogWriter labview_log(const RelaxationRecord& record);

/// Image file names that carry their camera time (`img_0003_t1.500s.tif`), for the file-name source
/// of frame times (io::time_from_file_name reads them back to the millisecond).
std::vector<std::string> timed_file_names(const std::vector<double>& times, const std::string& prefix = "img",
                                          const std::string& extension = ".tif");

}  // namespace tricot::synth
