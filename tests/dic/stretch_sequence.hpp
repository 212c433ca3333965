// A synthetic biaxial stretch sequence for the sequence tests: the continuous speckle pattern seen
// through x = c + diag(λx, λy)(X − c), λ growing linearly from 1 to its final value over the frames.
// The centre c stays put (docs/theory.md §10: the camera on its pantograph aims at the specimen centre).
#pragma once

#include <cmath>
#include <vector>

#include "tricot/dic/sequence.hpp"
#include "tricot/synth/speckle.hpp"

namespace tricot::test {

struct StretchSequence {
  int width = 240, height = 160;
  Vec2 centre{120, 80};
  Vec2 final_stretch{2.2, 1.4};  ///< λ at the last frame: 120 % and 40 %
  int frames = 10;               ///< images after the reference
  /// Material region tracked: ±half_roi around the centre in the reference image. With 31 px subsets
  /// it stays inside a 240×160 image up to λ = 2.2 × 1.4.
  Vec2 half_roi{40, 25};
  synth::SpeckleOptions speckle = [] {
    synth::SpeckleOptions o;
    o.subsamples = 2;  // 2×2 area samples per pixel: what the accuracy needs, at a quarter of the cost of 4×4
    return o;
  }();

  /// Frame k's rigid shift of the whole pattern (px); empty = none. A large first shift followed by
  /// none is a step that a velocity guess gets wrong (the rig's transverse setting, then the pull).
  std::vector<Vec2> shifts;

  Vec2 stretch(int k) const { return Vec2::Ones() + (final_stretch - Vec2::Ones()) * (double(k) / frames); }
  Vec2 shift(int k) const { return shifts.empty() ? Vec2::Zero() : shifts[k]; }
  /// Where the material point X of the reference is in frame k.
  Vec2 truth(const Vec2& X, int k) const { return centre + shift(k) + stretch(k).cwiseProduct(X - centre); }
  dic::Roi roi() const {
    return dic::Roi::rectangle(centre(0) - half_roi(0), centre(1) - half_roi(1), centre(0) + half_roi(0),
                               centre(1) + half_roi(1));
  }
  synth::SpecklePattern pattern() const { return synth::SpecklePattern(speckle, -10, -10, width + 10, height + 10); }
  image::Image image(const synth::SpecklePattern& P, int k) const {
    const Vec2 l = stretch(k);
    const Vec2 t = shift(k);
    return synth::render(P, width, height,
                         [&](const Vec2& x) { return Vec2(centre + (x - centre - t).cwiseQuotient(l)); });
  }
};

/// RMS distance between the tracked and the true positions of the ok points of frame f, and their count.
inline std::pair<double, int> rms_error(const StretchSequence& s, const dic::SequenceResult& r, int f) {
  double sum = 0;
  int n = 0;
  const dic::TrackedFrame& fr = r.frames[f];
  for (std::size_t k = 0; k < r.grid.size(); ++k)
    if (fr.status[k] == dic::PointStatus::ok) sum += (fr.x[k] - s.truth(r.grid[k].x, f)).squaredNorm(), ++n;
  return {n ? std::sqrt(sum / n) : NAN, n};
}

/// Tracks the whole sequence, rendering one image at a time.
inline dic::SequenceResult track(const StretchSequence& s, const dic::SequenceOptions& o) {
  const synth::SpecklePattern P = s.pattern();
  const image::Image ref = s.image(P, 0);
  dic::SequenceTracker t(ref, dic::make_grid(s.roi(), s.width, s.height, o.dic.icgn.subset_size, o.dic.step), o);
  for (int k = 1; k <= s.frames; ++k) t.add(s.image(P, k));
  return t.result();
}

}  // namespace tricot::test
