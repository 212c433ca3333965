// T3/T6/Q4/Q8 total-Lagrangian membrane elements (docs/theory.md §4, §6).
#include "tricot/fem/element.hpp"

#include <cmath>
#include <numbers>

namespace tricot::fem {

ShapeValues shape(ElementType type, const Vec2& xi) {
  static constexpr double kCorner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  const double x = xi(0), y = xi(1);
  ShapeValues s;
  if (is_triangle(type)) {
    // Area coordinates L0 = 1 − ξ − η, L1 = ξ, L2 = η; T6 adds the mid-sides 4 La Lb (edges 0-1, 1-2, 2-0).
    const double L[3] = {1 - x - y, x, y};
    const double dL[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
    if (type == ElementType::T3) {
      for (int a = 0; a < 3; ++a) s.N(a) = L[a], s.dN_dxi(a, 0) = dL[a][0], s.dN_dxi(a, 1) = dL[a][1];
      return s;
    }
    for (int a = 0; a < 3; ++a) {
      s.N(a) = L[a] * (2 * L[a] - 1);
      for (int j = 0; j < 2; ++j) s.dN_dxi(a, j) = (4 * L[a] - 1) * dL[a][j];
      const int b = (a + 1) % 3;
      s.N(3 + a) = 4 * L[a] * L[b];
      for (int j = 0; j < 2; ++j) s.dN_dxi(3 + a, j) = 4 * (dL[a][j] * L[b] + L[a] * dL[b][j]);
    }
    return s;
  }
  if (type == ElementType::Q4) {
    for (int a = 0; a < 4; ++a) {
      const double xa = kCorner[a][0], ya = kCorner[a][1];
      s.N(a) = 0.25 * (1 + x * xa) * (1 + y * ya);
      s.dN_dxi(a, 0) = 0.25 * xa * (1 + y * ya);
      s.dN_dxi(a, 1) = 0.25 * ya * (1 + x * xa);
    }
    return s;
  }
  // Serendipity Q8: corners ¼(1+ξξa)(1+ηηa)(ξξa+ηηa−1); mid-sides ½(1−ξ²)(1+ηηa) or ½(1+ξξa)(1−η²).
  for (int a = 0; a < 4; ++a) {
    const double xa = kCorner[a][0], ya = kCorner[a][1];
    const double p = 1 + x * xa, q = 1 + y * ya, r = x * xa + y * ya - 1;
    s.N(a) = 0.25 * p * q * r;
    s.dN_dxi(a, 0) = 0.25 * xa * q * (r + p);
    s.dN_dxi(a, 1) = 0.25 * ya * p * (r + q);
  }
  static constexpr double kMid[4][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  for (int m = 0; m < 4; ++m) {
    const double xa = kMid[m][0], ya = kMid[m][1];
    const int a = 4 + m;
    if (xa == 0) {
      s.N(a) = 0.5 * (1 - x * x) * (1 + y * ya);
      s.dN_dxi(a, 0) = -x * (1 + y * ya);
      s.dN_dxi(a, 1) = 0.5 * ya * (1 - x * x);
    } else {
      s.N(a) = 0.5 * (1 + x * xa) * (1 - y * y);
      s.dN_dxi(a, 0) = 0.5 * xa * (1 - y * y);
      s.dN_dxi(a, 1) = -y * (1 + x * xa);
    }
  }
  return s;
}

std::span<const QuadraturePoint> quadrature(ElementType type) {
  static const double g2 = 1 / std::sqrt(3.0), g3 = std::sqrt(0.6);
  static const std::array<QuadraturePoint, 4> q4 = {
      QuadraturePoint{{-g2, -g2}, 1}, {{g2, -g2}, 1}, {{g2, g2}, 1}, {{-g2, g2}, 1}};
  static const std::array<QuadraturePoint, 9> q8 = [] {
    const double p[3] = {-g3, 0, g3}, w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    std::array<QuadraturePoint, 9> r;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) r[3 * j + i] = {{p[i], p[j]}, w[i] * w[j]};
    return r;
  }();
  // Triangles on ξ, η ≥ 0, ξ + η ≤ 1 (area 1/2): T3 the centroid (exact for its constant gradients),
  // T6 the three-point rule of degree 2 (exact for the linear-elastic stiffness of a straight T6).
  static const std::array<QuadraturePoint, 1> t3 = {QuadraturePoint{{1.0 / 3, 1.0 / 3}, 0.5}};
  static const std::array<QuadraturePoint, 3> t6 = {
      QuadraturePoint{{1.0 / 6, 1.0 / 6}, 1.0 / 6}, {{2.0 / 3, 1.0 / 6}, 1.0 / 6}, {{1.0 / 6, 2.0 / 3}, 1.0 / 6}};
  switch (type) {
    case ElementType::Q4: return q4;
    case ElementType::Q8: return q8;
    case ElementType::T3: return t3;
    case ElementType::T6: return t6;
  }
  return q8;
}

ElementGeometry element_geometry(const Mesh& mesh, int e) {
  ElementGeometry g;
  g.nodes = nodes_per_element(mesh.type);
  const auto rule = quadrature(mesh.type);
  g.points = static_cast<int>(rule.size());
  g.min_detJ0 = INFINITY;
  g.region = mesh.region.empty() ? 0 : mesh.region[static_cast<size_t>(e)];
  const auto& c = mesh.connectivity[e];
  for (int q = 0; q < g.points; ++q) {
    const ShapeValues s = shape(mesh.type, rule[q].xi);
    Mat2 J = Mat2::Zero();  // J_ij = ∂X_i/∂ξ_j
    for (int a = 0; a < g.nodes; ++a) J += mesh.X.col(c[a]) * s.dN_dxi.row(a);
    const double detJ = J.determinant();
    g.min_detJ0 = std::min(g.min_detJ0, detJ);
    g.dA0[q] = rule[q].weight * detJ;
    g.dN_dX[q].setZero();
    g.dN_dX[q].topRows(g.nodes) = s.dN_dxi.topRows(g.nodes) * J.inverse();
  }
  return g;
}

ElementVector element_displacements(const Mesh& mesh, int e, const Eigen::VectorXd& u) {
  ElementVector ue = ElementVector::Zero();
  const int n = nodes_per_element(mesh.type);
  for (int a = 0; a < n; ++a) ue.segment<2>(2 * a) = u.segment<2>(2 * mesh.connectivity[e][a]);
  return ue;
}

Mat2 deformation_gradient(const ElementGeometry& g, int q, const ElementVector& ue) {
  Mat2 F = Mat2::Identity();
  for (int a = 0; a < g.nodes; ++a) F += ue.segment<2>(2 * a) * g.dN_dX[q].row(a);
  return F;
}

Mat2 deformation_gradient(const Mesh& mesh, int e, const Vec2& xi, const Eigen::VectorXd& u) {
  const ShapeValues s = shape(mesh.type, xi);
  const int n = nodes_per_element(mesh.type);
  const auto& c = mesh.connectivity[e];
  Mat2 J = Mat2::Zero(), H = Mat2::Zero();  // ∂X/∂ξ and ∂u/∂ξ
  for (int a = 0; a < n; ++a) {
    J += mesh.X.col(c[a]) * s.dN_dxi.row(a);
    H += u.segment<2>(2 * c[a]) * s.dN_dxi.row(a);
  }
  return Mat2::Identity() + H * J.inverse();
}

Mat2 material_axes(double angle_deg) {
  const double a = angle_deg * std::numbers::pi / 180;
  Mat2 Q;
  Q << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return Q;
}

namespace {

// B maps element dofs to flatten(δF): B(2i+j, 2a+i) = ∂N_a/∂X_j (row-major F, as in core/types.hpp).
// B is never formed. With G = ∂N/∂X (nodes × 2):
// - f = Bᵀ flatten(P) is G Pᵀ read row-major, i.e. f(2a+i) = Σ_j G(a, j) P(i, j);
// - K = Bᵀ A B splits into four node × node blocks K^{ik}(a, b) = K(2a+i, 2b+k) = G A^{ik} Gᵀ with
//   A^{ik}(j, l) = A(2i+j, 2k+l): dense NN × NN products that vectorize, accumulated over the points
//   and interleaved into K once per element. Where A is major-symmetric, K^{10} = (K^{01})ᵀ.
template <int NN>
ElementStatus response(const ElementGeometry& g, const ElementVector& ue, const Law& law, const Mat2& Q,
                       const LawRequest& req, LawOutput& lo, ElementResponse& out) {
  constexpr int D = 2 * NN;
  using NodeMat = Eigen::Matrix<double, NN, 2, Eigen::RowMajor>;  // (a, i) -> dof 2a+i
  using Block = Eigen::Matrix<double, NN, NN>;
  using Grad = Eigen::Matrix<double, NN, 2>;
  NodeMat f = NodeMat::Zero();
  Block K00, K01s, K01n, K10n, K11;  // K^{01} = K01s + K01n, K^{10} = K01sᵀ + K10n (n: non-symmetric points)
  if (req.tangent) K00.setZero(), K01s.setZero(), K01n.setZero(), K10n.setZero(), K11.setZero();
  out.symmetric_tangent = true;
  out.min_detF = INFINITY;
  int nc = 0;
  if (req.sensitivities) {
    nc = static_cast<int>(law.coefficients().size());
    out.df_dc.setZero(D, nc);
  }
  Eigen::Matrix<double, 2, NN> U;  // nodal displacements, column a = u_a
  for (int a = 0; a < NN; ++a) U.col(a) = ue.template segment<2>(2 * a);
  LawInput in;
  in.Q = Q;
  in.region = g.region;
  for (int q = 0; q < g.points; ++q) {
    const Grad G = g.dN_dX[q].template topRows<NN>();
    // F = I + U G entry by entry: as one 2 × 2 product GCC stores F in two 16-byte halves and reloads
    // it as one 32-byte vector, a store-forwarding stall that cost ~15 % of this function.
    const double F00 = 1 + U.row(0).dot(G.col(0)), F01 = U.row(0).dot(G.col(1));
    const double F10 = U.row(1).dot(G.col(0)), F11 = 1 + U.row(1).dot(G.col(1));
    in.F << F00, F01, F10, F11;
    const double detF = F00 * F11 - F01 * F10;
    out.min_detF = std::min(out.min_detF, detF);
    if (!(detF > 0)) return ElementStatus::inverted;
    law.evaluate(in, req, lo);
    if (!lo.P.allFinite() || (req.tangent && !lo.A.allFinite())) return ElementStatus::non_finite;
    const double w = g.dA0[q];
    f.noalias() += G * (w * lo.P.transpose());
    if (req.tangent) {
      const Mat4 A = w * lo.A;
      const double scale = A.cwiseAbs().maxCoeff();
      const bool symmetric = (A - A.transpose()).cwiseAbs().maxCoeff() <= 1e-10 * scale;
      out.symmetric_tangent = out.symmetric_tangent && symmetric;
      auto block = [&](int i, int k) -> Grad { return G * A.template block<2, 2>(2 * i, 2 * k); };
      K00.noalias() += block(0, 0) * G.transpose();
      K11.noalias() += block(1, 1) * G.transpose();
      if (symmetric) {
        K01s.noalias() += block(0, 1) * G.transpose();
      } else {
        K01n.noalias() += block(0, 1) * G.transpose();
        K10n.noalias() += block(1, 0) * G.transpose();
      }
    }
    if (req.sensitivities) {
      if (static_cast<int>(lo.dP_dc.size()) != nc) return ElementStatus::non_finite;
      for (int k = 0; k < nc; ++k) {
        if (!lo.dP_dc[k].allFinite()) return ElementStatus::non_finite;
        Eigen::Map<NodeMat>(out.df_dc.col(k).data()) += G * (w * lo.dP_dc[k].transpose());
      }
    }
  }
  if (NN < kMaxElementDofs / 2) out.f.setZero();
  Eigen::Map<NodeMat>(out.f.data()) = f;
  if (req.tangent) {
    if (NN < kMaxElementDofs / 2) out.K.setZero();
    for (int b = 0; b < NN; ++b)
      for (int a = 0; a < NN; ++a) {
        out.K(2 * a, 2 * b) = K00(a, b);
        out.K(2 * a, 2 * b + 1) = K01s(a, b) + K01n(a, b);
        out.K(2 * a + 1, 2 * b) = K01s(b, a) + K10n(a, b);
        out.K(2 * a + 1, 2 * b + 1) = K11(a, b);
      }
  }
  return ElementStatus::ok;
}

}  // namespace

ElementStatus element_response(const ElementGeometry& g, const ElementVector& ue, const Law& law, const Mat2& Q,
                               const LawRequest& request, LawOutput& scratch, ElementResponse& out) {
  switch (g.nodes) {
    case 3: return response<3>(g, ue, law, Q, request, scratch, out);
    case 4: return response<4>(g, ue, law, Q, request, scratch, out);
    case 6: return response<6>(g, ue, law, Q, request, scratch, out);
    default: return response<8>(g, ue, law, Q, request, scratch, out);
  }
}

}  // namespace tricot::fem
