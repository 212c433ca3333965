// 2-D finite-strain kinematics in closed form (see kinematics.hpp, docs/theory.md §4).
#include "tricot/core/kinematics.hpp"

#include <cmath>

namespace tricot {
namespace {

/// Below this |s| = t², G and G' use their series (truncation error < 1e-20; above it the closed
/// forms lose at most ~1e-13 relative to cancellation).
constexpr double kSeriesThreshold = 1e-3;
constexpr int kSeriesTerms = 8;

/// G(s) = atanh(√s)/√s = Σ_k s^k/(2k+1) (atan(√−s)/√−s for s < 0), s = t² < 1, and G'(s).
/// (ln λ1 − ln λ2)/(λ1 − λ2) = G(d²/m²)/m with λ1,2 = m ± d.
void log_ratio_series(double s, double& G, double& dG) {
  if (std::abs(s) < kSeriesThreshold) {
    G = 0;
    dG = 0;
    double p = 1;  // s^k
    for (int k = 0; k < kSeriesTerms; ++k) {
      G += p / (2 * k + 1);
      if (k + 1 < kSeriesTerms) dG += (k + 1) * p / (2 * k + 3);
      p *= s;
    }
    return;
  }
  const double r = std::sqrt(std::abs(s));
  G = s > 0 ? std::atanh(r) / r : std::atan(r) / r;
  dG = (1 / (1 - s) - G) / (2 * s);  // d/ds of atanh(√s)/√s (and of atan(√−s)/√−s for s < 0)
}

Vec4 flat_identity() { return {1, 0, 0, 1}; }

}  // namespace

PolarDecomposition polar_decomposition(const Mat2& F, PolarJacobians* J) {
  const double x = F(0, 0) + F(1, 1);
  const double y = F(1, 0) - F(0, 1);
  PolarDecomposition p;
  p.theta = std::atan2(y, x);
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  p.R << c, -s, s, c;
  p.U = p.R.transpose() * F;
  p.U(0, 1) = p.U(1, 0) = 0.5 * (p.U(0, 1) + p.U(1, 0));  // symmetric up to round-off; make it exact
  if (J) {
    const double r2 = x * x + y * y;
    J->dtheta_dF = Vec4(-y, -x, x, -y) / r2;
    Mat2 W;
    W << 0, -1, 1, 0;
    J->dR_dF = flatten(p.R * W) * J->dtheta_dF.transpose();
    J->dU_dF = left_product(p.R.transpose()) - flatten(W * p.U) * J->dtheta_dF.transpose();
  }
  return p;
}

double log_divided_difference(double a, double b) {
  const double m = 0.5 * (a + b);
  const double t = (a - b) / (a + b);
  double G, dG;
  log_ratio_series(t * t, G, dG);
  return G / m;
}

Mat2 log_spd(const Mat2& U, Mat4* J_logU_U) {
  const double a = U(0, 0), b = U(1, 1);
  const double m = 0.5 * (a + b);
  const double h = 0.5 * (a - b);
  const double d2 = h * h + U(0, 1) * U(1, 0);
  const double s = d2 / (m * m);
  const double detU = a * b - U(0, 1) * U(1, 0);
  double G, dG;
  log_ratio_series(s, G, dG);
  const double g = G / m;  // (ln λ1 − ln λ2)/(λ1 − λ2)
  const Mat2 D = U - m * Mat2::Identity();
  const Mat2 logU = 0.5 * std::log(detU) * Mat2::Identity() + g * D;
  if (J_logU_U) {
    const Vec4 I = flat_identity();
    const Vec4 dm = 0.5 * I;
    const Vec4 dd2(h, U(1, 0), U(0, 1), -h);
    const Vec4 ds = dd2 / (m * m) - 2 * d2 / (m * m * m) * dm;
    const Vec4 dlndet = Vec4(b, -U(1, 0), -U(0, 1), a) / detU;
    const Vec4 dg = dG / m * ds - G / (m * m) * dm;
    *J_logU_U =
        0.5 * I * dlndet.transpose() + flatten(D) * dg.transpose() + g * (Mat4::Identity() - I * dm.transpose());
  }
  return logU;
}

Mat2 green_lagrange(const Mat2& F, Mat4* J_E_F) {
  if (J_E_F) {
    J_E_F->setZero();
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k)
          for (int l = 0; l < 2; ++l) (*J_E_F)(2 * i + j, 2 * k + l) = 0.5 * ((j == l) * F(k, i) + (i == l) * F(k, j));
  }
  return 0.5 * (F.transpose() * F - Mat2::Identity());
}

Mat4 left_product(const Mat2& A) {
  Mat4 J = Mat4::Zero();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) J(2 * i + j, 2 * k + j) = A(i, k);
  return J;
}

Mat4 right_product(const Mat2& B) {
  Mat4 J = Mat4::Zero();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int l = 0; l < 2; ++l) J(2 * i + j, 2 * i + l) = B(l, j);
  return J;
}

Mat4 sandwich_product(const Mat2& A, const Mat2& B) { return left_product(A) * right_product(B); }

}  // namespace tricot
