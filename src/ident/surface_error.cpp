// Eq. (9) error (THEORY §9).
#include "tricot/ident/surface_error.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "tricot/core/error.hpp"

namespace tricot::ident {

void StrainDomain::validate() const {
  auto check = [](const char* key, double lo, double hi) {
    if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi)
      throw InputError(Location{"", 0, std::string("eq9.practical.") + key}, "not a strain interval",
                       "[" + format_number(lo) + ", " + format_number(hi) + "]", "finite bounds, min <= max");
  };
  check("course", eC_min, eC_max);
  check("wale", eW_min, eW_max);
}

Eq9Error eq9_error(const std::vector<SurfacePoint>& points, const std::function<double(double, double)>& identified,
                   const StrainDomain& practical) {
  practical.validate();
  Eq9Error e;
  double sum = 0, sum_p = 0;
  double cmin = 1e300, cmax = -1e300, wmin = 1e300, wmax = -1e300;
  for (const SurfacePoint& p : points) {
    if (p.force == 0 || !std::isfinite(p.force)) continue;
    const double d = std::abs(identified(p.eC, p.eW) - p.force) / std::abs(p.force);
    sum += d, ++e.points_whole;
    cmin = std::min(cmin, p.eC), cmax = std::max(cmax, p.eC), wmin = std::min(wmin, p.eW), wmax = std::max(wmax, p.eW);
    if (practical.contains(p.eC, p.eW)) sum_p += d, ++e.points_practical;
  }
  if (e.points_whole == 0)
    throw InputError(Location{"", 0, "eq9.points"}, "no experimental point with a non-zero force",
                     std::to_string(points.size()) + " points", "at least one point with F != 0");
  if (e.points_practical == 0)
    throw InputError(Location{"", 0, "eq9.practical"}, "the practical domain holds no experimental point",
                     "course [" + format_number(practical.eC_min) + ", " + format_number(practical.eC_max) + "] x wale [" +
                         format_number(practical.eW_min) + ", " + format_number(practical.eW_max) + "]",
                     "a domain that meets the data (course [" + format_number(cmin) + ", " + format_number(cmax) +
                         "], wale [" + format_number(wmin) + ", " + format_number(wmax) + "])");
  e.whole = sum / e.points_whole;
  e.practical = sum_p / e.points_practical;
  return e;
}

}  // namespace tricot::ident
