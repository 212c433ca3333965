// Integer-pixel starting point for IC-GN: FFT cross-correlation of a subset over a search window
// (docs/theory.md §10; the normalised cross-correlation is computed in the Fourier domain by OpenCV's
// matchTemplate, TM_CCOEFF_NORMED, i.e. ZNCC at every integer shift).
#pragma once

#include "tricot/dic/icgn.hpp"

namespace tricot::dic {

/// The best integer shift of a subset within a search window.
struct IntegerMatch {
  Vec2 displacement{0, 0};  ///< px, integer
  double zncc = 0;          ///< ZNCC at that shift (rigid subset)
  bool found = false;       ///< false when the subset or the window is blank or outside the image
};

/// Searches the N×N subset at `centre` (rounded to a pixel) of `reference` in `current` over shifts
/// `predicted` ± `search_radius` px (window clipped to the image).
IntegerMatch integer_search(const image::Image& reference, const image::Image& current, const Vec2& centre,
                            int subset_size, const Vec2& predicted, int search_radius);

/// A full first-order starting shape at a seed: the integer shift at the seed, and the displacement
/// gradient from integer shifts of four satellite subsets one subset size away (central differences,
/// one-sided at the border). This is what lets one-step correlation start at 45 % stretch, where a
/// rigid guess is outside IC-GN's basin. `found` is false when the centre itself has no match.
struct SeedGuess {
  Shape p = Shape::Zero();
  double zncc = 0;
  bool found = false;
};
SeedGuess seed_guess(const Frame& reference, const Frame& current, const Vec2& centre, int subset_size,
                     int search_radius, const Vec2& predicted = Vec2::Zero());

/// The fall-back when the local search fails: a large one-step motion (45 % stretch from the first image,
/// a displacement far beyond the search radius). A template of 2N − 1 px, about twice the subset, is built
/// from the reference's B-spline through candidate stretches F = diag(sx, sy), sx, sy ∈ [0.8, 1.9], and
/// matched over the whole current image at half resolution; the best candidate is then refined at full
/// resolution on a finer grid of stretches. The larger template keeps self-similar speckle (a 31 px
/// subset of a Boolean-model pattern matches elsewhere with ZNCC ≈ 0.9) from seeding at a wrong place.
/// Costs about a second on a 2000×1000 image: correlate_pair uses it at most twice per image pair.
SeedGuess wide_seed_guess(const Frame& reference, const Frame& current, const Vec2& centre, int subset_size);

}  // namespace tricot::dic
