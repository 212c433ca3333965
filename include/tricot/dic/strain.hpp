// Green–Lagrange strain from tracked points by a local least-squares plane fit (THEORY.md §4, §10;
// Pan, Asundi, Xie & Gao 2009, doi:10.1016/j.optlaseng.2009.02.008 for the pointwise local fit).
//
// Around each point the current positions of its neighbours within a square window of the grid are
// fitted by an affine map x(X) = x_c + F (X − X_c) (least squares), which gives the deformation gradient
// F = ∂x/∂X and E = ½(FᵀF − I). exy is the tensor component E₁₂ (half the engineering shear).
#pragma once

#include <vector>

#include "tricot/dic/grid.hpp"

namespace tricot::dic {

struct StrainOptions {
  int window = 5;                   ///< points per side of the square fitting window, odd, 3–51
  double min_fraction = 0.35;       ///< 0–1: the fit needs this fraction of the window's points (and ≥ 4); 0.35 keeps grid corners
  void validate() const;
};

/// The strain at one point. Invalid points (too few good neighbours) carry NaN.
struct StrainPoint {
  Mat2 F = Mat2::Identity();  ///< deformation gradient ∂x/∂X
  double exx = 0, eyy = 0, exy = 0;
  bool valid = false;
};

/// Green–Lagrange strains of every grid point. `X` are reference positions (one per grid point),
/// `x` current positions, `good[k]` whether x[k] is a measurement.
std::vector<StrainPoint> green_lagrange(const std::vector<GridPoint>& grid, const std::vector<Vec2>& x,
                                        const std::vector<char>& good, const StrainOptions& options);

}  // namespace tricot::dic
