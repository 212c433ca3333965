#include "tricot/lab/specimen.hpp"

#include <fmt/format.h>

#include <cmath>

#include "tricot/core/error.hpp"

namespace tricot::lab {

void SpecimenGeometry::validate() const {
  auto bad = [](const char* key, double v, const char* expected) {
    throw InputError({"", 0, key}, "out of range", format_number(v), expected);
  };
  if (!(width_mm > 0) || !std::isfinite(width_mm)) bad("specimen.width_mm", width_mm, "> 0 mm");
  if (!(free_length_mm > 0) || !std::isfinite(free_length_mm)) bad("specimen.free_length_mm", free_length_mm, "> 0 mm");
  if (!(tolerance_mm >= 0) || !std::isfinite(tolerance_mm)) bad("specimen.tolerance_mm", tolerance_mm, "≥ 0 mm");
}

FoldedPoints fold_to_quarter(const dic::PhysicalFrame& frame, const SpecimenGeometry& geometry,
                             const std::vector<Vec2>& x_px) {
  frame.validate();
  geometry.validate();
  FoldedPoints f;
  f.frame = frame;
  for (std::size_t k = 0; k < x_px.size(); ++k) {
    if (!x_px[k].allFinite())
      throw InputError({"", 0, "points"}, "point " + std::to_string(k) + " is not a finite position");
    const Vec2 P = frame.point(x_px[k]);
    const Vec2 s(P(0) < 0 ? -1 : 1, P(1) < 0 ? -1 : 1);
    f.X.push_back(P.cwiseAbs());
    f.sign.push_back(s);
    f.quadrant.push_back(s(0) > 0 ? (s(1) > 0 ? 1 : 4) : (s(1) > 0 ? 2 : 3));
    const bool in = f.X.back()(0) <= geometry.half_width() + geometry.tolerance_mm &&
                    f.X.back()(1) <= geometry.half_length() + geometry.tolerance_mm;
    f.inside.push_back(in);
    if (!in) ++f.outside;
  }
  return f;
}

Vec2 FoldedPoints::displacement(std::size_t k, const Vec2& u_px) const {
  return frame.vector(u_px).cwiseProduct(sign.at(k));
}

Vec2 FoldedPoints::sigma(std::size_t k, const Vec2& sigma_px) const {
  (void)sign.at(k);
  const Mat2 Q = frame.axes();
  const Vec2 var = Q.cwiseAbs2() * sigma_px.cwiseAbs2();
  return frame.mm_per_px * var.cwiseSqrt();
}

std::string FoldedPoints::outside_report(const SpecimenGeometry& g) const {
  if (outside == 0) return "";
  return fmt::format("{} of {} points lie outside the {:g} × {:g} mm specimen", outside, size(), g.width_mm,
                     g.free_length_mm);
}

double scale_from_points(const Vec2& a_px, const Vec2& b_px, double distance_mm) {
  if (!a_px.allFinite() || !b_px.allFinite() || (a_px - b_px).norm() == 0)
    throw InputError({"", 0, "physical.scale_points"}, "the two points must be distinct and finite",
                     fmt::format("({}, {}) and ({}, {}) px", a_px(0), a_px(1), b_px(0), b_px(1)), "two distinct pixels");
  if (!(distance_mm > 0) || !std::isfinite(distance_mm))
    throw InputError({"", 0, "physical.scale_distance_mm"}, "out of range", format_number(distance_mm), "> 0 mm");
  return distance_mm / (a_px - b_px).norm();
}

}  // namespace tricot::lab
