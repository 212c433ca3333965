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

QuarterField fold_sequence(const dic::SequenceResult& sequence, const dic::PhysicalFrame& frame,
                           const SpecimenGeometry& geometry, FieldKind kind) {
  const std::size_t images = sequence.frames.size();
  if (images < 2) throw InputError({"", 0, "dic"}, "too few images for a field", std::to_string(images), "at least 2");
  if (kind == FieldKind::incremental && sequence.increments.size() + 1 != images)
    throw InputError({"", 0, "dic.fixed_point_fields"}, "the sequence has no fixed-point increments",
                     std::to_string(sequence.increments.size()),
                     std::to_string(images - 1) + " increments (fixed_point_fields = true)");
  std::vector<Vec2> x0;
  for (const auto& g : sequence.grid) x0.push_back(g.x);
  const FoldedPoints folded = fold_to_quarter(frame, geometry, x0);
  QuarterField q;
  q.kind = kind;
  const int steps = static_cast<int>(images) - 1;
  auto measured = [&](int step, std::size_t p) {
    return kind == FieldKind::cumulative ? sequence.frames[std::size_t(step) + 1].status[p] == dic::PointStatus::ok
                                         : sequence.increments[std::size_t(step)].status[p] == dic::PointStatus::ok;
  };
  for (std::size_t p = 0; p < x0.size(); ++p) {
    if (!folded.inside[p]) {
      ++q.outside;
      continue;
    }
    bool all = sequence.frames[0].status[p] == dic::PointStatus::ok;
    for (int k = 0; k < steps && all; ++k) all = measured(k, p);
    if (!all) {
      ++q.incomplete;
      continue;
    }
    q.point_ids.push_back(static_cast<int>(p));
    q.X.push_back(folded.X[p]);
  }
  const int n = static_cast<int>(q.point_ids.size());
  q.u.resize(steps, n), q.v.resize(steps, n), q.sigma_u.resize(steps, n), q.sigma_v.resize(steps, n);
  for (int k = 0; k < steps; ++k)
    for (int a = 0; a < n; ++a) {
      const std::size_t p = std::size_t(q.point_ids[std::size_t(a)]);
      Vec2 u_px, s_px;
      if (kind == FieldKind::cumulative) {
        u_px = sequence.frames[std::size_t(k) + 1].x[p] - x0[p];
        s_px = sequence.frames[std::size_t(k) + 1].sigma[p];
      } else {
        u_px = sequence.increments[std::size_t(k)].u[p];
        s_px = sequence.increments[std::size_t(k)].sigma[p];
      }
      const Vec2 u = folded.displacement(p, u_px), s = folded.sigma(p, s_px);
      q.u(k, a) = u(0), q.v(k, a) = u(1), q.sigma_u(k, a) = s(0), q.sigma_v(k, a) = s(1);
    }
  q.report = fmt::format("{} of {} points kept; {} outside the {:g} × {:g} mm specimen, {} not measured in every image",
                         n, x0.size(), q.outside, geometry.width_mm, geometry.free_length_mm, q.incomplete);
  return q;
}

std::vector<double> grip_from_field(const QuarterField& field, const SpecimenGeometry& geometry) {
  std::vector<double> grip(std::size_t(field.u.rows()), 0.0);
  double yy = 0;
  for (const Vec2& X : field.X) yy += X(1) * X(1);
  if (!(yy > 0))
    throw InputError({"", 0, "dic"}, "no field point off the axis Y = 0: the grip's motion cannot be estimated");
  for (Eigen::Index k = 0; k < field.v.rows(); ++k) {
    double vy = 0;
    for (std::size_t a = 0; a < field.X.size(); ++a) vy += field.v(k, Eigen::Index(a)) * field.X[a](1);
    grip[std::size_t(k)] = vy / yy * geometry.half_length();
  }
  return grip;
}

double scale_from_points(const Vec2& a_px, const Vec2& b_px, double distance_mm) {
  if (!a_px.allFinite() || !b_px.allFinite() || (a_px - b_px).norm() == 0)
    throw InputError({"", 0, "physical.scale_points"}, "the two points must be distinct and finite",
                     fmt::format("({}, {}) and ({}, {}) px", a_px(0), a_px(1), b_px(0), b_px(1)),
                     "two distinct pixels");
  if (!(distance_mm > 0) || !std::isfinite(distance_mm))
    throw InputError({"", 0, "physical.scale_distance_mm"}, "out of range", format_number(distance_mm), "> 0 mm");
  return distance_mm / (a_px - b_px).norm();
}

}  // namespace tricot::lab
