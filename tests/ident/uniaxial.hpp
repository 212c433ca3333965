// A small uniaxial Mooney–Rivlin test (docs/theory.md §5, §6; paper §3.3) for the FE identification tests:
// a clamped strip, quarter model 10 × 25 mm, Q8.
#pragma once

#include <vector>

#include "tricot/fem/mesh.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/mooney_rivlin.hpp"

namespace tricot::ident::test {

constexpr double kWidth = 10, kHeight = 25;  // quarter model, mm

/// Force control: the grip force rises to `force` N in `steps` equal steps (the paper's uniaxial
/// test, whose data is the grip's displacement). Displacement control: the grip moves to
/// 0.8 × height (the strip stretches to λ ≈ 1.8).
inline fem::TestModel uniaxial(int nx, int ny, int steps, fem::GripControl control, double force = 7.0,
                               double grading = 1) {
  fem::MeshOptions o;
  o.width = kWidth, o.height = kHeight, o.nx = nx, o.ny = ny, o.type = fem::ElementType::Q8;
  o.grading = grading;
  fem::TestModel t;
  t.name = "uniaxial";
  t.mesh = fem::make_quarter_mesh(o);
  t.control = control;
  t.grip_holds_x = true;  // clamped: the strip necks, the field is not uniform
  const double last = control == fem::GripControl::force ? force : 0.8 * kHeight;
  for (int k = 1; k <= steps; ++k) t.loads.push_back(last * k / steps);
  return t;
}

/// A grid of nx × ny points inside the quarter specimen, from 1 mm off its axes to x_max and 1 mm
/// below the grip. Fixed (incremental) points must stay inside the necking strip: x_max ≈ W/2.
inline Eigen::Matrix2Xd field_points(int nx, int ny, double x_max = kWidth - 1) {
  Eigen::Matrix2Xd p(2, nx * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      p.col(j * nx + i) = Vec2(1 + (x_max - 1) * i / (nx - 1), 1 + (kHeight - 2) * j / (ny - 1));
  return p;
}

}  // namespace tricot::ident::test
