// Pictures of a DIC frame for a person to look at: displacement, strain and ZNCC maps drawn over the
// image (docs/design.md: one overlay per frame). Each tracked point is painted as its deformed grid cell,
// x_k + F·(±step/2, ±step/2), so the maps follow the material. OpenCV draws; it stays out of this header.
#pragma once

#include <string>
#include <vector>

#include "tricot/dic/grid.hpp"
#include "tricot/dic/sequence.hpp"
#include "tricot/image/image.hpp"

namespace tricot::dic {

/// Which quantity a panel shows.
enum class OverlayField { displacement, u, v, exx, eyy, exy, zncc };
const char* to_string(OverlayField f);  ///< "|u| (px)", "u (px)", ..., "ZNCC"

struct OverlayOptions {
  /// The panels, laid out two per row. Default: |u|, exx, eyy, ZNCC.
  std::vector<OverlayField> panels{OverlayField::displacement, OverlayField::exx, OverlayField::eyy,
                                   OverlayField::zncc};
  int panel_width = 800;  ///< px, 100–10000: each panel is scaled down (never up) to this width
  double opacity = 0.65;  ///< 0–1: weight of the colour over the image
  /// Colour range of each panel: the 2nd–98th percentile of the frame's values (robust to outliers),
  /// except ZNCC, which spans [zncc_floor, 1].
  double zncc_floor = 0.9;  ///< 0–1

  /// The config keys of [output] these options hold (core/options.hpp); `panels` is the verb's (words).
  static auto keys() {
    using O = OverlayOptions;
    return std::tuple{
        option(&O::panel_width, "output.panel_width", "px: each map is scaled down to at most this width.", 100, 10000),
        option(&O::zncc_floor, "output.zncc_floor", "The ZNCC map's colours span [zncc_floor, 1].", 0, 0.999)};
  }
  /// Throws InputError naming the key (`output.panel_width`, ...) when a field is out of range.
  void validate() const;
};

/// Draws frame `f` of a sequence over its image `current` (the frame's own image, in which f.x are the
/// positions). `grid` and `step` are those of the sequence (grid[k].x in the reference image).
/// Points that are not ok are left uncoloured; in frame 0 they are marked gray.
image::RgbImage draw_overlay(const image::Image& current, const std::vector<GridPoint>& grid, int step,
                             const TrackedFrame& f, const OverlayOptions& options = {});

}  // namespace tricot::dic
