// Small linear least-squares problems (at most 6 unknowns) accumulated row by row as normal equations:
// the hinge fits of sync.cpp and the variable projection of relaxation.cpp. Plain loops: Eigen's
// AVX-512 kernels draw false-positive warnings from GCC 12 at this size, and nothing here needs more.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace tricot::lab {

class NormalEquations {
 public:
  explicit NormalEquations(int unknowns) : m_(unknowns) {}

  /// Adds the row φ (m values) with its datum y.
  void add(const double* phi, double y) {
    for (int i = 0; i < m_; ++i) {
      r_[i] += phi[i] * y;
      for (int j = 0; j < m_; ++j) A_[i][j] += phi[i] * phi[j];
    }
    yy_ += y * y, sy_ += y, ++n_;
  }
  int rows() const { return n_; }
  /// Σ (y − ȳ)²
  double total() const { return n_ > 0 ? yy_ - sy_ * sy_ / n_ : 0; }
  /// min_c |y − Φc|² and the coefficients c. Columns are scaled to a unit diagonal (whatever the units);
  /// a column that is all zero gets a zero coefficient through a tiny ridge.
  double solve(std::array<double, 6>* c = nullptr) const {
    double s[6], L[6][6] = {}, z[6];
    for (int j = 0; j < m_; ++j) s[j] = A_[j][j] > 0 ? 1 / std::sqrt(A_[j][j]) : 0;
    for (int i = 0; i < m_; ++i)
      for (int j = 0; j <= i; ++j) {
        double v = s[i] * A_[i][j] * s[j] + (i == j ? 1e-12 : 0);
        for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
        L[i][j] = i == j ? std::sqrt(std::max(v, 1e-300)) : v / L[j][j];
      }
    double explained = 0;
    for (int i = 0; i < m_; ++i) {  // L z = S r; then |y − Φc|² = yᵀy − |z|²
      double v = s[i] * r_[i];
      for (int k = 0; k < i; ++k) v -= L[i][k] * z[k];
      z[i] = v / L[i][i];
      explained += z[i] * z[i];
    }
    if (c) {
      for (int i = m_; i-- > 0;) {  // Lᵀ (c / s) = z
        double v = z[i];
        for (int k = i + 1; k < m_; ++k) v -= L[k][i] * (*c)[k];
        (*c)[i] = v / L[i][i];
      }
      for (int i = 0; i < m_; ++i) (*c)[i] *= s[i];
    }
    return std::max(0.0, yy_ - explained);
  }

 private:
  int m_;
  double A_[6][6] = {}, r_[6] = {}, yy_ = 0, sy_ = 0;
  int n_ = 0;
};

}  // namespace tricot::lab
