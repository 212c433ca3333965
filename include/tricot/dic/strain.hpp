// Green–Lagrange strain from tracked points by a local least-squares plane fit (docs/theory.md §4, §10;
// Pan, Asundi, Xie & Gao 2009, doi:10.1016/j.optlaseng.2009.02.008 for the pointwise local fit).
//
// Around each point the current positions of its neighbours within a square window of the grid are
// fitted by an affine map x(X) = x_c + F (X − X_c) (least squares), which gives the deformation gradient
// F = ∂x/∂X and E = ½(FᵀF − I). exy is the tensor component E₁₂ (half the engineering shear).
#pragma once

#include <vector>

#include "tricot/core/options.hpp"
#include "tricot/dic/grid.hpp"

namespace tricot::dic {

struct StrainOptions {
  int window = 5;  ///< points per side of the square fitting window, odd, 3–51
  double min_fraction =
      0.35;  ///< 0–1: the fit needs this fraction of the window's points (and ≥ 4); 0.35 keeps grid corners

  /// The config keys of [strain] (core/options.hpp).
  static auto keys() {
    using O = StrainOptions;
    return std::tuple{option(&O::window, "strain.window", "Grid points per side of the fitting window, odd.", 3, 51),
                      option(&O::min_fraction, "strain.min_fraction",
                             "The fit needs this fraction of the window's points to be ok.", 0, 1)};
  }
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

/// The virtual strain gauge (VSG) of these strains, px: the length of reference image that one strain
/// value depends on, VSG = (window − 1) × step + subset (issue 16). This is the convention of the iDICs
/// Good Practices Guide for DIC (Jones & Iadicola, eds., 2018, §5.3.2 and the glossary,
/// doi:10.32720/idics/gpg.ed1) used by the DIC Challenge 2.0 (Reu et al., Experimental Mechanics 62,
/// 2022): the fit's window spans (window − 1) × step px of subset centres, and each centre sees half a
/// subset beyond it. It is a length, not a resolution: for first-order subsets the strain of a sinusoid
/// keeps 90 % of its amplitude at periods ≥ about 2.7 VSG (strain_transfer; docs/validation.md).
int virtual_strain_gauge(int subset_size, int step, int window);

/// The predicted fraction of a sinusoidal strain's amplitude that these strains keep, for a
/// displacement u = A sin(2πX/p) along a grid axis (small A), measured by first-order uniform subsets
/// of `subset_size` px: the subset acts on the displacement as a box, sinc(πN/p) (sinc x = sin x / x),
/// and the least-squares slope over `window` grid points `step` px apart as
///     T_fit(p) = Σ_k k sin(2πks/p) / ((2πs/p) Σ_k k²),  k = −h … h,  h = (window − 1)/2,
/// so T(p) = sinc(πN/p) T_fit(p). subset_size = 0 gives T_fit alone (the fit of exact displacements).
double strain_transfer(double period, int subset_size, int step, int window);

}  // namespace tricot::dic
