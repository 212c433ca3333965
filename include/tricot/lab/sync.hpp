// Synchronisation of the load cell with the camera (docs/theory.md §1, "forces known at the same instants
// that pictures are taken"). The two have their own clocks: an image taken at camera time t_k happened
// at log time t_k + δ, δ = clock_offset_s. δ is estimated, never assumed zero:
//   - crosshead: the log's cross-head displacement c(t) is cross-correlated with the grip displacement
//     g_k that DIC measures: δ maximises |r|, r the correlation of c(t_k + δ) with a polynomial in g_k
//     of degree `crosshead_degree` (±√R²; for degree 1 Pearson's r of an affine relation: units, signs
//     and the quarter model's factor ½ do not matter), on a grid of one log sample,
//     then refined by golden-section search on the piecewise-linear interpolant (sub-sample δ);
//   - onset: without a cross-head column, the onset of force in the log is matched with the onset of
//     motion in the images. The images give the grip's motion as a constant-speed machine makes it:
//     rest until t0, constant speed until t1 (the stop, if the images show a hold), each the hinge of
//     a least-squares fit y = b + a·max(0, t − t0) over the frames up to `onset_fraction` of the
//     travel (from either end). The log's force must then follow that motion:
//         F(t) = tare + Σ_{j=1..force_degree} p_j · (clamp(t − δ, t0, t1) − t0)^j,
//     and δ minimises the residual over the whole log (grid of one log sample, then golden section).
//     The force starts (and stops) rising when the motion does; a J-shaped force that starts softly
//     leaves its stop to fix δ, hence the hold after the ramp when one was recorded;
//   - given: a clock offset in the options overrides both.
// The tare is the mean force over the log samples before the motion starts (log time), removed from
// every force. Each image's force is the mean of the log's piecewise-linear force over its exposure
// [t_k + δ − e/2, t_k + δ + e/2] (frame times stamp the middle of the exposure).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace tricot::lab {

/// A load-cell record, in the load cell's clock.
struct LoadLog {
  std::string source;             ///< the file, for messages (may be empty)
  std::vector<double> time;       ///< s, strictly increasing
  std::vector<double> force;      ///< N, one per time
  std::vector<double> crosshead;  ///< mm (any unit), one per time, or empty when the log has none

  bool has_crosshead() const { return !crosshead.empty(); }
  /// Throws InputError (file = source, key `log.<column>`) for fewer than 4 samples, lengths that
  /// differ, a non-finite value or a time that does not increase.
  void validate() const;
};

/// The images as the synchronisation sees them: camera times and the grip motion DIC measured.
struct ImageTimes {
  std::vector<double> time;        ///< s, camera clock, strictly increasing
  std::vector<double> grip;        ///< grip displacement per image (mm), from DIC; frame 0 at rest
  std::vector<std::string> names;  ///< image file names for messages, or empty (then "frame k", 0-based)

  std::string name(std::size_t k) const;
  /// Throws InputError (key `images.time` / `images.grip`) for fewer than 3 images, lengths that
  /// differ, a non-finite value or a time that does not increase.
  void validate() const;
};

/// Frame times from a frame rate and the first image's time (camera clock): start_s + k / fps.
/// Throws InputError naming `images.fps` / `images.count` when fps ≤ 0 or count < 1.
std::vector<double> frame_times(int count, double fps, double start_s = 0);

/// How δ was fixed.
enum class SyncMethod {
  given,      ///< SyncOptions::clock_offset_s
  crosshead,  ///< cross-correlation of the log's cross-head with the grip motion
  onset,      ///< onset of force matched with onset of motion
};
const char* to_string(SyncMethod m);  ///< "given", "crosshead", "onset"

struct SyncOptions {
  /// Log clock minus camera clock, s. When set, it is used as is (method `given`).
  std::optional<double> clock_offset_s;
  /// Force at rest, N. When set, it is used as is; otherwise it is estimated before the motion.
  std::optional<double> tare_N;
  /// Search range of δ, s, > 0: |δ| ≤ max_offset_s.
  double max_offset_s = 10;
  /// Exposure time of each image, s, ≥ 0 (0 = the force at the instant, linearly interpolated).
  double exposure_s = 0;
  /// Onset fits use the record up to where it has risen by this fraction of its range, (0, 1].
  double onset_fraction = 0.3;
  /// onset method: degree of the polynomial force–motion relation, 1–5.
  int force_degree = 3;
  /// crosshead method: degree of the polynomial relation of the cross-head to the grip motion DIC
  /// measures, 1–4 (1 = affine, Pearson's r). 3 absorbs a grip proxy that is not proportional to the
  /// cross-head (a field seen only at the specimen's centre, whose strain runs ahead of the grip's).
  int crosshead_degree = 3;
  /// Log samples this close (s, ≥ 0) before the motion's onset are left out of the tare.
  double tare_margin_s = 0.05;

  /// Throws InputError naming `sync.<field>` when out of range.
  void validate() const;
};

enum class SyncTermination {
  found,            ///< δ given, or the criterion's optimum lies inside the search range
  at_search_limit,  ///< the optimum lies at ±max_offset_s: the true offset may lie beyond (raise it)
};

struct SyncResult {
  SyncTermination termination = SyncTermination::found;
  SyncMethod method = SyncMethod::given;
  double clock_offset_s = 0;  ///< δ: log time = camera time + δ
  double tare_N = 0;          ///< removed from every force
  bool tare_given = false;
  int tare_samples = 0;              ///< log samples averaged for the tare (0 when given)
  double motion_onset_log_s = 0;     ///< log time at which the grip starts moving (NaN when unknown)
  double motion_onset_camera_s = 0;  ///< onset method: camera time of the same (NaN otherwise)
  std::vector<double> log_time;      ///< per image: t_k + δ
  std::vector<double> force;         ///< per image: mean log force over its exposure, minus the tare, N
  /// per image: mean log cross-head over its exposure, minus its value at the first image (empty
  /// without a cross-head column). Half of it is the quarter model's grip displacement.
  std::vector<double> crosshead;
  /// The criterion that fixed δ, against the lag δ (s): the Pearson correlation of grip and cross-head
  /// (crosshead), or the R² of the force-follows-motion fit (onset); empty
  /// when δ was given. For the sync plot.
  std::vector<double> lag_s, correlation;
  double peak_correlation = 0;  ///< the criterion at δ
  std::string message;

  /// One line: "clock offset 0.370 s (crosshead, r = 0.99998), tare 0.512 N from 150 samples".
  std::string brief_report() const;
};

/// Finds δ and the tare and resamples the force at every image. Validates its inputs, then throws
/// InputError when the log does not cover some image's exposure (naming the first image left out),
/// when the grip does not move, or when the onset method finds no rest before the motion.
SyncResult synchronise(const LoadLog& log, const ImageTimes& images, const SyncOptions& options = {});

/// One load step of an experiment (`forces.csv`): image k ≥ 1 (image 0 is the unloaded reference).
struct ForceStep {
  int step = 0;                ///< 1-based, = the image's index
  double time_s = 0;           ///< camera time since image 0
  double grip_mm = 0;          ///< grip displacement of the quarter model (the FE load of the step)
  double force_N = 0;          ///< full-specimen grip force, tare removed
  double force_per_width = 0;  ///< force per unit initial width, N/mm
};
/// The steps of a synchronised test. `grip_mm` per image (image 0 included), from DIC or half the
/// synchronised cross-head. Throws InputError for lengths that differ from the images' or a width ≤ 0
/// (key `specimen.width_mm`).
std::vector<ForceStep> force_steps(const ImageTimes& images, const SyncResult& sync, const std::vector<double>& grip_mm,
                                   double width_mm);

/// The mean of the piecewise-linear f(t) over [a, b] (its value at a when a == b). The caller
/// guarantees t.front() ≤ a ≤ b ≤ t.back().
double mean_over(const std::vector<double>& t, const std::vector<double>& f, double a, double b);

/// The hinge fits of the onset method: the t0 minimising Σ (y − b − Σ_{j=1..degree} a_j max(0, t − t0)^j)²
/// over the given samples, searched between t.front() and t.back(). `rss` (optional) receives the
/// minimum residual sum of squares.
double hinge_onset(const std::vector<double>& t, const std::vector<double>& y, int degree, double* rss = nullptr);

}  // namespace tricot::lab
