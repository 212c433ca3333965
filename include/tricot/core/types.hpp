// Small fixed-size types shared by every engine.
#pragma once

#include <Eigen/Core>

namespace tricot {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
/// A fourth-order 2-D tensor A_ijkl stored as a 4×4 matrix, row (i,j) -> 2i+j, column (k,l) -> 2k+l.
/// Used for tangents dP/dF: A(2i+j, 2k+l) = ∂P_ij/∂F_kl.
using Mat4 = Eigen::Matrix4d;
using Vec4 = Eigen::Vector4d;

/// Row-major flattening of a 2×2 tensor, matching the Mat4 index convention.
inline Vec4 flatten(const Mat2& A) { return {A(0, 0), A(0, 1), A(1, 0), A(1, 1)}; }
inline Mat2 unflatten(const Vec4& a) {
  Mat2 A;
  A << a(0), a(1), a(2), a(3);
  return A;
}

}  // namespace tricot
