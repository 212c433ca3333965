#include "tricot/dic/physical.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "tricot/core/error.hpp"

namespace tricot::dic {

void PhysicalFrame::validate() const {
  if (!(mm_per_px > 0) || !std::isfinite(mm_per_px))
    throw InputError(Location{"", 0, "physical.mm_per_px"}, "out of range", format_number(mm_per_px), "> 0 mm/px");
  if (!centre_px.allFinite()) throw InputError(Location{"", 0, "physical.centre_px"}, "not a finite point");
  if (!std::isfinite(angle_deg)) throw InputError(Location{"", 0, "physical.angle_deg"}, "not a finite number");
}

Mat2 PhysicalFrame::axes() const {
  // On screen (y up), the specimen X axis is at angle θ: e_X = (cos θ, sin θ), e_Y = (−sin θ, cos θ).
  // In image coordinates (y down) those directions are (cos θ, −sin θ) and (−sin θ, −cos θ); Q's rows are
  // the specimen axes expressed in image coordinates (Y flipped when the specimen Y points down on screen).
  const double t = angle_deg * std::numbers::pi / 180, c = std::cos(t), s = std::sin(t);
  Mat2 Q;
  Q << c, -s, -s, -c;
  if (!y_up) Q.row(1) *= -1;
  return Q;
}

}  // namespace tricot::dic
