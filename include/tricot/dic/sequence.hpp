// DIC over an image sequence (docs/theory.md §10, paper §3.1.3): material points tracked from the first
// image through every later one, and fixed-point incremental fields between consecutive images.
//
// Modes (the image a frame k is correlated against, its "reference" r):
//   incremental  r = k − 1 always: subsets are re-formed square in every image, which is what lets
//                correlation survive > 100 % strain. Positions accumulate: x_k = x_{k−1} + u(x_{k−1}),
//                with u measured by a subset centred exactly on the tracked point (no interpolation of
//                a displacement field, so noise-free drift comes only from IC-GN's own random error).
//   reference    r = 0 always: no accumulation, but subsets must match through the whole deformation.
//   automatic    r stays until the frame's mean ZNCC drops below `update_zncc` or points start failing;
//                then r becomes k − 1 (Ncorr's "step analysis").
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tricot/core/progress.hpp"
#include "tricot/dic/correlate.hpp"
#include "tricot/dic/grid.hpp"
#include "tricot/dic/strain.hpp"

namespace tricot::dic {

enum class SequenceMode { incremental, reference, automatic };
const char* to_string(SequenceMode m);  ///< "incremental", "reference", "auto"

struct SequenceOptions {
  DicOptions dic;
  SequenceMode mode = SequenceMode::incremental;
  /// automatic: update the reference when the frame's mean ZNCC falls below this, 0–1.
  double update_zncc = 0.95;
  /// automatic: ... or when more than this fraction of the tracked points fail, 0–1.
  double update_loss = 0.02;
  StrainOptions strain;
  /// Also correlate the fixed grid between consecutive images (the paper's WIMA-style incremental
  /// fields). Costs a second correlation per frame.
  bool fixed_point_fields = false;
  /// Keep every frame in SequenceResult::frames (and every increment). false: only the latest frame
  /// and increment are kept, so that memory stays bounded for any number of frames; the caller writes
  /// each frame as add() returns it (project::run_dic streams points.csv that way).
  bool keep_frames = true;

  /// The config keys of [dic] these options hold besides dic's (core/options.hpp).
  static auto keys() {
    using O = SequenceOptions;
    return std::tuple{
        option(&O::mode, "dic.mode",
               "incremental: each image against the previous one (survives > 100 % strain; positions "
               "accumulate).\nreference: every image against the first. auto: keep the reference until the "
               "correlation drops,\nthen move it to the previous image (Ncorr's step analysis).",
               {{SequenceMode::incremental, "incremental"},
                {SequenceMode::reference, "reference"},
                {SequenceMode::automatic, "auto"}}),
        option(&O::update_zncc, "dic.update_zncc",
               "auto mode: update the reference when a frame's mean ZNCC drops below this.", 0, 1),
        option(&O::update_loss, "dic.update_loss", "auto mode: ... or when more than this fraction of the points fail.",
               0, 1)};
  }
  void validate() const;
};

/// The tracked points in one frame. Index k is the same material point in every frame. A point
/// rejected in frame 0 (`no_texture`, `out_of_image`) keeps that status in every frame; a point that
/// fails later reports why in that frame and `lost` in the frames after it (incremental and auto
/// modes; reference mode retries it in every frame).
struct TrackedFrame {
  int frame = 0;             ///< 0 = reference image
  int reference_frame = 0;   ///< the image this frame was correlated against
  std::vector<Vec2> x;       ///< current position, px (NaN when not measured)
  std::vector<double> zncc;  ///< of the last match (1 in frame 0)
  std::vector<PointStatus> status;
  std::vector<StrainPoint> strain;  ///< Green–Lagrange, relative to frame 0
  /// σ of x (px, image axes) from image noise (PointMatch::sigma): 0 in frame 0; a position that
  /// accumulates matches (incremental, or auto after a reference update) adds their variances,
  /// treating the matches as independent. NaN when not measured.
  std::vector<Vec2> sigma;
  int ok = 0;
  double mean_zncc = 0;
  double seconds = 0;
  /// Where `seconds` went: preparing the image (B-spline coefficients, gradients), correlating the
  /// tracked points (seeds, propagation, IC-GN), the strain fit, the fixed-point incremental field.
  struct Stages {
    double prepare = 0, correlate = 0, strain = 0, increments = 0;
  } stages;
  std::string message;
};

/// Displacements from image `from` to image `to` at the fixed grid centres of the first image.
struct IncrementField {
  int from = 0, to = 0;
  std::vector<Vec2> u;      ///< px (NaN when not ok)
  std::vector<Vec2> sigma;  ///< σ of u, px (PointMatch::sigma; NaN when not ok)
  std::vector<double> zncc;
  std::vector<PointStatus> status;
};

enum class SequenceTermination {
  completed,  ///< every frame was correlated and some points survived to the end
  all_lost,   ///< every point was lost before the last frame
};

struct SequenceResult {
  std::vector<GridPoint> grid;             ///< the material points: grid[k].x is the position in frame 0
  std::vector<TrackedFrame> frames;        ///< one per image, frame 0 first
  std::vector<IncrementField> increments;  ///< frames 1.. (when fixed_point_fields)
  SequenceTermination termination = SequenceTermination::completed;
  std::string message;
  double seconds = 0;
  /// One line: "41 frames, 1131 points: 1131/1131 ok in the last frame, mean ZNCC 0.9987, 2.1 s" (the
  /// frames up to the last one tracked, kept or not).
  std::string brief_report() const;
};

/// Where a checkpoint (SequenceTracker::checkpoint) stands: the images a resumed tracker needs.
struct SequenceResumePoint {
  int next_frame = 1;       ///< the frame the next add() correlates; frames 0..next_frame−1 are done
  int reference_frame = 0;  ///< the image the tracker correlates against (frame r)
};

/// Tracks points frame by frame, so that a long sequence never needs every image in memory:
///     SequenceTracker t(reference, grid, options);  for (...) t.add(next_image);  t.result();
/// Only the reference image r and the previous image are held (prepared for IC-GN), whatever the
/// number of frames; with SequenceOptions::keep_frames = false the results are not accumulated either.
class SequenceTracker {
 public:
  /// Validates the options. `grid` usually comes from make_grid on the reference image.
  SequenceTracker(const image::Image& reference, std::vector<GridPoint> grid, SequenceOptions options,
                  Reporter reporter = {});
  /// Resumes from `checkpoint` (checkpoint() of a tracker with the same grid and options):
  /// `reference` is the image of resume_point(checkpoint).reference_frame, `previous` that of
  /// next_frame − 1. The frames added afterwards are bit for bit those of the uninterrupted tracker.
  /// result().frames starts with the checkpoint's last frame. Throws InputError (key `resume`) when
  /// the checkpoint is unreadable or was made with another grid.
  SequenceTracker(const image::Image& reference, const image::Image& previous, std::vector<GridPoint> grid,
                  SequenceOptions options, const std::string& checkpoint, Reporter reporter = {});
  ~SequenceTracker();
  SequenceTracker(const SequenceTracker&) = delete;
  SequenceTracker& operator=(const SequenceTracker&) = delete;

  /// Correlates the next image (same size as the reference: the caller checks) and returns its frame.
  const TrackedFrame& add(const image::Image& next);
  /// Everything so far (termination and message set).
  const SequenceResult& result();

  /// The tracker's whole state after the last add(), binary and exact (doubles as bits): what the
  /// second constructor needs to go on as if never stopped.
  std::string checkpoint() const;
  /// Where `checkpoint` stands. Throws InputError (key `resume`) when it is not a checkpoint.
  static SequenceResumePoint resume_point(const std::string& checkpoint);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// Convenience for tests: the whole sequence at once (images[0] is the reference).
SequenceResult track_sequence(const std::vector<image::Image>& images, const Roi& roi, const SequenceOptions& options,
                              Reporter reporter = {});

}  // namespace tricot::dic
