// Deformation gradients the law and kinematics tests check at (manif's rule: identity, tiny and large
// states), and the rotations and shears they are built from.
#pragma once

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "tricot/core/types.hpp"

namespace tricot::test {

/// Rotation by `a` radians (counter-clockwise).
inline Mat2 rotation(double a) {
  Mat2 Q;
  Q << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return Q;
}

/// Rotation by `deg` degrees (counter-clockwise).
inline Mat2 rot(double deg) { return rotation(deg * std::numbers::pi / 180); }

/// Simple shear F = [[1, γ], [0, 1]] (docs/theory.md §4).
inline Mat2 shear(double gamma) {
  Mat2 F;
  F << 1, gamma, 0, 1;
  return F;
}

/// A named deformation gradient (the name goes into failure messages).
struct State {
  std::string name;
  Mat2 F;
};

/// The states of the orthotropic membrane laws (corotational, response surface, reference fabric):
/// identity, a small strain, the law's own large stretch, a stretch turned by 120° and the law's own
/// general F (stretch and shear) turned by 200°. The large states are the caller's, sized to its law.
inline std::vector<State> orthotropic_law_states(const State& large_stretch, const Mat2& general) {
  Mat2 small;
  small << 1 + 1e-4, 2e-4, -1e-4, 1 - 3e-5;
  return {{"identity", Mat2::Identity()},
          {"small strain", small},
          large_stretch,
          {"large rotation 120 deg", rot(120) * Mat2(Vec2(1.6, 0.9).asDiagonal())},
          {"combined rotation 200 deg, stretch and shear", rot(200) * general}};
}

/// The states of the isotropic hyperelastic laws (Mooney–Rivlin, neo-Hookean): identity, a small
/// strain, the law's own stretch 3, a stretch turned by 0.7 rad and a simple shear γ = 0.5.
inline std::vector<State> isotropic_law_states(const Mat2& stretch_3) {
  Mat2 small, U;
  small << 1.001, 0.0004, -0.0003, 0.9995;
  U << 2.0, 0.3, 0.3, 0.7;
  return {{"identity", Mat2::Identity()},
          {"small strain", small},
          {"stretch 3", stretch_3},
          {"rotation and stretch", rotation(0.7) * U},
          {"simple shear", shear(0.5)}};
}

}  // namespace tricot::test
