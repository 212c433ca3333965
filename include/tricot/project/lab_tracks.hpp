// Point tracks made by other tools, read as they come (issue 29): a lab's tracked points and its
// per-frame force in, with no converter, for `tricot experiment` ([[test]] tracks = FILE).
//
// Supported track files (tracks_format):
//   long  one row per point and frame: frame, point, x, y (columns named by frame_column, point_column,
//         x_column, y_column; any delimiter, header lines, decimal comma and units as io::read_log).
//   wide  one row per frame: frame, then two columns per point named <point>_x, <point>_y (a unit in
//         brackets or a _px / _mm suffix allowed: `top_pin_x [px]`, `top_pin_x_px`).
//   dice  a folder of DICe's DICe_solution_NNNN.txt files, one per frame (frame = NNNN): SUBSET_ID,
//         COORDINATE_X, COORDINATE_Y (reference position, px), DISPLACEMENT_X, DISPLACEMENT_Y, and
//         SIGMA (−1 marks a subset DICe lost in that frame). A point is SUBSET_ID; its position is
//         COORDINATE + DISPLACEMENT.
// Positions are in px or mm (tracks_unit; a header's units must agree with it and with each other).
// The per-frame force (frame_forces = FILE) is a table with a frame column and a force column and is
// synchronised by frame number: its frames must be the tracks' frames.
//
// A one-sided pull (one clamp still, the other pulling): with two clamp markers ([[test]] clamps =
// [A, B]) the specimen's rigid motion is removed — every position has the clamps' mean displacement
// subtracted, so that the clamps move apart symmetrically about a still centre, which is the quarter
// model's (docs/theory.md §6). The grip displacement of the quarter is half the change of the clamps'
// distance along the pull, and the free length is their distance in the reference frame.
#pragma once

#include <string>
#include <vector>

#include "tricot/core/types.hpp"
#include "tricot/lab/specimen.hpp"
#include "tricot/lab/sync.hpp"
#include "tricot/project/lab_spec.hpp"

namespace tricot::project {

/// Tracked points, one row per frame.
struct PointTracks {
  std::string file;                                  ///< the track file (or DICe folder), for messages
  std::string unit = "px";                           ///< px or mm
  std::vector<long> frames;                          ///< frame numbers, increasing
  std::vector<int> lines;                            ///< the line of each frame's first row in `file` (0 = unknown)
  std::vector<std::string> points;                   ///< point names, in order of first appearance
  std::vector<std::vector<Vec2>> x;                  ///< [frame][point]: position; NaN where the tool lost the point
  std::size_t find(const std::string& point) const;  ///< index of a point, or points.size()
};

/// Reads a [[test]]'s `tracks` (tracks_format, tracks_unit, *_column keys). Throws FileError when the
/// file or folder is missing, InputError naming FILE:LINE: KEY for: a long table whose frame lacks a
/// point, a wide table with an empty cell, columns in px and mm mixed (or against tracks_unit), a
/// frame given twice.
PointTracks read_point_tracks(const LabTestSpec& test);

/// A per-frame force: a frame column and a force column (N).
struct FrameForces {
  std::string file;
  std::vector<long> frames;
  std::vector<int> lines;
  std::vector<double> force_N;
};
/// Reads a [[test]]'s `frame_forces` (frame_column, force_column). InputError at a bad cell.
FrameForces read_frame_forces(const LabTestSpec& test);

/// One test of point tracks, ready for the experiment folder.
struct TracksTest {
  std::vector<lab::ForceStep> steps;  ///< steps 1.. (frames after the reference, every frame_stride-th)
  std::vector<long> step_frames;      ///< the frame number of each step
  long reference_frame = 0;           ///< the unloaded reference (the tracks' first frame)
  lab::QuarterField field;            ///< the field points (folded into the quarter for the quarter model)
  lab::SpecimenGeometry geometry;     ///< width as given, free length from the clamps when they are given
  double mm_per_px = 1;               ///< the test's scale (1 for tracks in mm)
  bool rigid_motion_removed = false;  ///< the clamps' mean displacement subtracted
  /// A full model whose frame is the clamps' midpoint (px tracks with clamps): the specimen is the
  /// width × free-length rectangle about it, and the points beyond it are left out.
  bool centred_on_clamps = false;
  /// The full model's clamps (with `clamps` given): each marker's displacement per step, mm, in the
  /// mesh frame, for the grips' conditions (DIR/<test>/clamps.csv).
  struct ClampMotion {
    std::string marker;
    std::vector<Vec2> u;
  };
  std::vector<ClampMotion> clamp_motion;
  std::string report;  ///< one line: frames, steps, points kept
};

/// Reads a [[test]] of point tracks (of a validated LabSpec: its force file, two clamps or none) and its
/// per-frame force and makes its steps and field. `physical` is the lab file's [physical] (scale,
/// centre, axes), which the test's own mm_per_px overrides.
/// `full` = false: the quarter model, the points folded into X, Y ≥ 0, those beyond the specimen's
/// rectangle left out, and the clamps' mean displacement subtracted (with clamps given); true: the
/// whole specimen, every point where it is (tracks in mm are points of the mesh frame as they stand,
/// tracks in px go through [physical], centred on the clamps' midpoint when they are given) and
/// nothing subtracted; with clamps, each marker's displacement per step (clamp_motion).
/// Throws InputError naming FILE:LINE: KEY for: a force file whose frames are not the tracks' (the
/// first frame in one and not the other), a clamp that is not a tracked point, clamps whose distance
/// does not change (a clamp marker that does not move), a scale missing for tracks in px.
TracksTest tracks_test(const LabTestSpec& test, const LabPhysicalSpec& physical, bool full);

}  // namespace tricot::project
