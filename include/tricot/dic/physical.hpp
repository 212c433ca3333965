// From image pixels to specimen coordinates (docs/theory.md §10: the camera on its pantograph aims at the
// specimen centre, which therefore stays at a fixed pixel).
//
// X_specimen = Q · s · (x_px − c_px), with s the pixel size (mm/px), c_px the specimen-centre pixel
// and Q the rotation (and, since image y points down, reflection) that takes image axes to specimen
// axes. With angle θ (degrees, counter-clockwise as seen on screen, from the image x axis to the
// specimen X axis) and y_up, Q = R(−θ) · diag(1, −1) ... see physical.cpp for the exact matrix.
#pragma once

#include "tricot/core/types.hpp"

namespace tricot::dic {

struct PhysicalFrame {
  double mm_per_px = 1.0;  ///< pixel size, > 0
  Vec2 centre_px{0, 0};    ///< pixel of the specimen centre (fixed in every image)
  double angle_deg = 0.0;  ///< specimen X axis, counter-clockwise on screen from the image x axis
  bool y_up = true;        ///< specimen Y axis points up on screen (image y points down)

  void validate() const;
  /// Q: image axes (px, y down) → specimen axes. Orthogonal; det = −1 when y_up.
  Mat2 axes() const;
  /// A pixel position → specimen coordinates, mm.
  Vec2 point(const Vec2& x_px) const { return axes() * (mm_per_px * (x_px - centre_px)); }
  /// A displacement in px → mm in specimen axes.
  Vec2 vector(const Vec2& u_px) const { return axes() * (mm_per_px * u_px); }
  /// A strain tensor in image axes → specimen axes, Q E Qᵀ (dimensionless; shear changes sign with y_up).
  Mat2 tensor(const Mat2& E) const { return axes() * E * axes().transpose(); }
};

}  // namespace tricot::dic
