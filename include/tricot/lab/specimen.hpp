// DIC points in the specimen's coordinates of the quarter model (THEORY.md §6, §10). The camera on
// its pantograph aims at the specimen centre, a fixed pixel; dic::PhysicalFrame takes pixels to mm in
// specimen axes (X across, Y along the pull, origin at the centre). The FE model is the quarter
// X ≥ 0, Y ≥ 0 with symmetry on both axes, so points of the other three quadrants are folded into it:
//     X → |X|, Y → |Y|,   u_X → sign(X)·u_X,   u_Y → sign(Y)·u_Y
// (a point on an axis keeps its sign, +1). Points that fall outside the specimen are flagged and
// counted, never silently dropped: the caller decides what to do with them and reports the count.
#pragma once

#include <string>
#include <vector>

#include "tricot/core/types.hpp"
#include "tricot/dic/physical.hpp"

namespace tricot::lab {

/// The specimen's size, the full specimen (not the quarter).
struct SpecimenGeometry {
  double width_mm = 150;         ///< between the free (or guided) edges, > 0
  double free_length_mm = 150;   ///< between the clips, > 0
  double tolerance_mm = 0;       ///< points up to this far beyond the outline count as inside, ≥ 0

  double half_width() const { return 0.5 * width_mm; }
  double half_length() const { return 0.5 * free_length_mm; }
  /// Throws InputError naming `specimen.<field>` when out of range.
  void validate() const;
};

/// Points folded into the quarter model.
struct FoldedPoints {
  dic::PhysicalFrame frame;
  std::vector<Vec2> X;          ///< quarter-model position, mm (X ≥ 0, Y ≥ 0), every point
  std::vector<Vec2> sign;       ///< (sign X, sign Y) of the full-specimen position, each ±1
  std::vector<int> quadrant;    ///< 1: X ≥ 0, Y ≥ 0; 2: X < 0, Y ≥ 0; 3: X < 0, Y < 0; 4: X ≥ 0, Y < 0
  std::vector<bool> inside;     ///< within the reference specimen (± tolerance)
  int outside = 0;              ///< how many are not inside

  std::size_t size() const { return X.size(); }
  /// A displacement of point k measured in px (image axes) → mm in the quarter model's axes.
  Vec2 displacement(std::size_t k, const Vec2& u_px) const;
  /// The standard deviations of a displacement (σ_u, σ_v in px, image axes, independent) → mm in
  /// the quarter model's axes (a rotation mixes them; the fold's signs do not change them).
  Vec2 sigma(std::size_t k, const Vec2& sigma_px) const;
  /// "12 of 480 points lie outside the 150 × 150 mm specimen" or "" when none.
  std::string outside_report(const SpecimenGeometry& g) const;
};

/// Folds image points (px) into the quarter model. Validates the frame (a scale of zero is an
/// InputError naming `physical.mm_per_px`) and the geometry.
FoldedPoints fold_to_quarter(const dic::PhysicalFrame& frame, const SpecimenGeometry& geometry,
                             const std::vector<Vec2>& x_px);

/// The pixel size (mm/px) from two image points a known distance apart (a ruler in the picture).
/// Throws InputError (key `physical.scale_points`) when the points coincide or are not finite, or
/// (key `physical.scale_distance_mm`) when the distance is not > 0.
double scale_from_points(const Vec2& a_px, const Vec2& b_px, double distance_mm);

}  // namespace tricot::lab
