// DIC points in the specimen's coordinates of the quarter model (docs/theory.md §6, §10). The camera on
// its pantograph aims at the specimen centre, a fixed pixel; dic::PhysicalFrame takes pixels to mm in
// specimen axes (X across, Y along the pull, origin at the centre). The FE model is the quarter
// X ≥ 0, Y ≥ 0 with symmetry on both axes, so points of the other three quadrants are folded into it:
//     X → |X|, Y → |Y|,   u_X → sign(X)·u_X,   u_Y → sign(Y)·u_Y
// (a point on an axis keeps its sign, +1). Points that fall outside the specimen are flagged and
// counted, never silently dropped: the caller decides what to do with them and reports the count.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "tricot/core/types.hpp"
#include "tricot/dic/physical.hpp"
#include "tricot/dic/sequence.hpp"

namespace tricot::lab {

/// The specimen's size, the full specimen (not the quarter).
struct SpecimenGeometry {
  double width_mm = 150;        ///< between the free (or guided) edges, > 0
  double free_length_mm = 150;  ///< between the clips, > 0
  double tolerance_mm = 0;      ///< points up to this far beyond the outline count as inside, ≥ 0

  double half_width() const { return 0.5 * width_mm; }
  double half_length() const { return 0.5 * free_length_mm; }
  /// Throws InputError naming `specimen.<field>` when out of range.
  void validate() const;
};

/// Points folded into the quarter model.
struct FoldedPoints {
  dic::PhysicalFrame frame;
  std::vector<Vec2> X;        ///< quarter-model position, mm (X ≥ 0, Y ≥ 0), every point
  std::vector<Vec2> sign;     ///< (sign X, sign Y) of the full-specimen position, each ±1
  std::vector<int> quadrant;  ///< 1: X ≥ 0, Y ≥ 0; 2: X < 0, Y ≥ 0; 3: X < 0, Y < 0; 4: X ≥ 0, Y < 0
  std::vector<bool> inside;   ///< within the reference specimen (± tolerance)
  int outside = 0;            ///< how many are not inside

  std::size_t size() const { return X.size(); }
  /// A displacement of point k measured in px (image axes) → mm in the quarter model's axes.
  Vec2 displacement(std::size_t k, const Vec2& u_px) const;
  /// The standard deviations of a displacement (σ_u, σ_v in px, image axes, independent) → mm in
  /// the quarter model's axes (a rotation mixes them; the fold's signs do not change them).
  Vec2 sigma(std::size_t k, const Vec2& sigma_px) const;
  /// "12 of 480 points lie outside the 150 × 150 mm specimen" or "" when none.
  std::string outside_report(const SpecimenGeometry& g) const;
};

/// What a field holds (docs/theory.md §7, ident::FieldKind has the same meaning).
enum class FieldKind {
  cumulative,   ///< material points tracked from image 0: u(X, t_k) = x_k − x_0, X = x_0 folded
  incremental,  ///< fixed grid points: u = x(t_k) − x(t_{k−1}) at the grid centres of image 0
};

/// A DIC sequence in the quarter model's mm, ready for an experiment's field: steps are the images
/// 1..n−1 (image 0 is the unloaded reference, not a step). Only points inside the specimen that are
/// measured (`ok`) in every step are kept; the others are counted, never silently dropped.
struct QuarterField {
  FieldKind kind = FieldKind::cumulative;
  std::vector<int> point_ids;        ///< index of the kept points in the DIC grid
  std::vector<Vec2> X;               ///< quarter-model position of each kept point, mm
  Eigen::MatrixXd u, v;              ///< steps × kept points, mm, quarter-model axes
  Eigen::MatrixXd sigma_u, sigma_v;  ///< their σ from IC-GN, mm
  int outside = 0;                   ///< grid points outside the specimen
  int incomplete = 0;                ///< grid points inside but not measured in some step
  std::string report;                ///< one line: kept, outside, incomplete
};

/// Folds a DIC sequence (dic::track_sequence, dic::SequenceTracker) into the quarter model. The
/// incremental kind needs the sequence's fixed-point fields. Throws InputError (key `dic`) when the
/// sequence holds fewer than 2 images, or no increments for the incremental kind.
QuarterField fold_sequence(const dic::SequenceResult& sequence, const dic::PhysicalFrame& frame,
                           const SpecimenGeometry& geometry, FieldKind kind);

/// The grip displacement of the quarter model (u_Y at Y = H, mm) estimated per step from a cumulative
/// field: the least-squares slope of v = a·Y over the kept points (odd in Y by symmetry), times H.
/// Exact for a strain homogeneous along the pull; otherwise a proxy proportional to the grip's motion,
/// which is all the synchronisation needs (it matches shapes, not sizes). Step 0 first.
std::vector<double> grip_from_field(const QuarterField& field, const SpecimenGeometry& geometry);

/// Folds image points (px) into the quarter model. Validates the frame (a scale of zero is an
/// InputError naming `physical.mm_per_px`) and the geometry.
FoldedPoints fold_to_quarter(const dic::PhysicalFrame& frame, const SpecimenGeometry& geometry,
                             const std::vector<Vec2>& x_px);

/// The pixel size (mm/px) from two image points a known distance apart (a ruler in the picture).
/// Throws InputError (key `physical.scale_points`) when the points coincide or are not finite, or
/// (key `physical.scale_distance_mm`) when the distance is not > 0.
double scale_from_points(const Vec2& a_px, const Vec2& b_px, double distance_mm);

}  // namespace tricot::lab
