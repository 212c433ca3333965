// T3/T6/Q4/Q8 membrane elements in the total-Lagrangian form (docs/theory.md §4, §6): shape functions,
// Gauss quadrature, and the element internal force f = ∫ Bᵀ P dA0, stiffness K = ∫ Bᵀ A B dA0 and
// coefficient sensitivity ∂f/∂c_k = ∫ Bᵀ ∂P/∂c_k dA0 (docs/theory.md §7).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <span>

#include "tricot/core/types.hpp"
#include "tricot/fem/law.hpp"
#include "tricot/fem/mesh.hpp"

namespace tricot::fem {

/// Shape functions N_a(ξ) and ∂N_a/∂ξ_j of one element type at one point; rows past the
/// element's node count (3 for T3, 4 for Q4, 6 for T6) are zero.
struct ShapeValues {
  Eigen::Matrix<double, 8, 1> N = Eigen::Matrix<double, 8, 1>::Zero();
  Eigen::Matrix<double, 8, 2> dN_dxi = Eigen::Matrix<double, 8, 2>::Zero();
};
/// Q4: bilinear; Q8: serendipity, node order as in Mesh (corners CCW from (−1,−1), then mid-sides) on
/// ξ ∈ [−1, 1]²; T3: linear, T6: quadratic, corners at (0, 0), (1, 0), (0, 1), on ξ, η ≥ 0, ξ + η ≤ 1.
ShapeValues shape(ElementType type, const Vec2& xi);

struct QuadraturePoint {
  Vec2 xi;
  double weight;
};
/// Gauss rule of an element type: 2×2 for Q4, 3×3 for Q8, 1 point for T3, 3 points for T6.
std::span<const QuadraturePoint> quadrature(ElementType type);

/// Element dofs: local dof 2a+i = u_i of local node a. 16 = the Q8 count; Q4 uses the first 8.
constexpr int kMaxElementDofs = 16;
constexpr int kMaxQuadraturePoints = 9;
using ElementVector = Eigen::Matrix<double, kMaxElementDofs, 1>;
using ElementMatrix = Eigen::Matrix<double, kMaxElementDofs, kMaxElementDofs>;

/// The reference geometry of one element at its quadrature points, computed once per mesh.
struct ElementGeometry {
  int nodes = 0;                                                        ///< 3, 4, 6 or 8
  int points = 0;                                                       ///< 1, 4, 3 or 9
  std::array<Eigen::Matrix<double, 8, 2>, kMaxQuadraturePoints> dN_dX;  ///< ∂N_a/∂X_j
  std::array<double, kMaxQuadraturePoints> dA0;                         ///< Gauss weight × det(∂X/∂ξ)
  /// Smallest det(∂X/∂ξ) over the points; ≤ 0 means the element is inverted in the reference mesh.
  double min_detJ0 = 0;
  int region = 0;  ///< Mesh::region of the element (0 without regions), passed to the law
};
ElementGeometry element_geometry(const Mesh& mesh, int e);

/// Element nodal displacements: ue(2a+i) = u_i of local node a, taken from the global u (2·nodes).
ElementVector element_displacements(const Mesh& mesh, int e, const Eigen::VectorXd& u);

/// F = I + Σ_a ue_a ⊗ ∂N_a/∂X at quadrature point q.
Mat2 deformation_gradient(const ElementGeometry& g, int q, const ElementVector& ue);
/// F = I + ∂u/∂X at any natural point ξ of element e (e.g. the centre, for output).
Mat2 deformation_gradient(const Mesh& mesh, int e, const Vec2& xi, const Eigen::VectorXd& u);

/// Material axes from the test's material angle (degrees from x to the course): Q.col(0) = course
/// (cos a, sin a), Q.col(1) = wale (−sin a, cos a).
Mat2 material_axes(double angle_deg);

enum class ElementStatus {
  ok,
  inverted,    ///< det F ≤ 0 at a quadrature point
  non_finite,  ///< the law returned a non-finite stress or tangent
};

/// What one element returns. Only the leading 2·nodes rows/columns are meaningful.
struct ElementResponse {
  ElementVector f;                ///< internal force ∫ Bᵀ P dA0 [N]
  ElementMatrix K;                ///< ∂f/∂ue = ∫ Bᵀ A B dA0 (when the request asks the tangent)
  Eigen::MatrixXd df_dc;          ///< 2·nodes × coefficients: ∫ Bᵀ ∂P/∂c_k dA0 (when asked)
  bool symmetric_tangent = true;  ///< every A had major symmetry (then K is symmetric)
  double min_detF = 1;            ///< smallest det F over the quadrature points
};

/// Evaluates one element at its nodal displacements ue with `law` (docs/theory.md §4). `scratch` is the
/// caller's reusable law output (one per thread). Returns the status; `out` is valid only when ok.
ElementStatus element_response(const ElementGeometry& g, const ElementVector& ue, const Law& law, const Mat2& Q,
                               const LawRequest& request, LawOutput& scratch, ElementResponse& out);

}  // namespace tricot::fem
