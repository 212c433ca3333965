// DIC over an image sequence (THEORY.md §10, paper §3.1.3): material points tracked from the first
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

  void validate() const;
};

/// The tracked points in one frame. Index k is the same material point in every frame. A point
/// rejected in frame 0 (`no_texture`, `out_of_image`) keeps that status in every frame; a point that
/// fails later reports why in that frame and `lost` in the frames after it (incremental and auto
/// modes; reference mode retries it in every frame).
struct TrackedFrame {
  int frame = 0;              ///< 0 = reference image
  int reference_frame = 0;    ///< the image this frame was correlated against
  std::vector<Vec2> x;        ///< current position, px (NaN when not measured)
  std::vector<double> zncc;   ///< of the last match (1 in frame 0)
  std::vector<PointStatus> status;
  std::vector<StrainPoint> strain;  ///< Green–Lagrange, relative to frame 0
  /// σ of x (px, image axes) from image noise (PointMatch::sigma): 0 in frame 0; a position that
  /// accumulates matches (incremental, or auto after a reference update) adds their variances,
  /// treating the matches as independent. NaN when not measured.
  std::vector<Vec2> sigma;
  int ok = 0;
  double mean_zncc = 0;
  double seconds = 0;
  std::string message;
};

/// Displacements from image `from` to image `to` at the fixed grid centres of the first image.
struct IncrementField {
  int from = 0, to = 0;
  std::vector<Vec2> u;  ///< px (NaN when not ok)
  std::vector<Vec2> sigma;  ///< σ of u, px (PointMatch::sigma; NaN when not ok)
  std::vector<double> zncc;
  std::vector<PointStatus> status;
};

enum class SequenceTermination {
  completed,   ///< every frame was correlated and some points survived to the end
  all_lost,    ///< every point was lost before the last frame
};

struct SequenceResult {
  std::vector<GridPoint> grid;          ///< the material points: grid[k].x is the position in frame 0
  std::vector<TrackedFrame> frames;     ///< one per image, frame 0 first
  std::vector<IncrementField> increments;  ///< frames 1.. (when fixed_point_fields)
  SequenceTermination termination = SequenceTermination::completed;
  std::string message;
  double seconds = 0;
};

/// Tracks points frame by frame, so that a long sequence never needs every image in memory:
///     SequenceTracker t(reference, grid, options);  for (...) t.add(next_image);  t.result();
class SequenceTracker {
 public:
  /// Validates the options. `grid` usually comes from make_grid on the reference image.
  SequenceTracker(const image::Image& reference, std::vector<GridPoint> grid, SequenceOptions options,
                  Reporter reporter = {});
  ~SequenceTracker();
  SequenceTracker(const SequenceTracker&) = delete;
  SequenceTracker& operator=(const SequenceTracker&) = delete;

  /// Correlates the next image (same size as the reference: the caller checks) and returns its frame.
  const TrackedFrame& add(const image::Image& next);
  /// Everything so far (termination and message set).
  const SequenceResult& result();

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// Convenience for tests: the whole sequence at once (images[0] is the reference).
SequenceResult track_sequence(const std::vector<image::Image>& images, const Roi& roi,
                              const SequenceOptions& options, Reporter reporter = {});

}  // namespace tricot::dic
