// The material-stability barrier (include/tricot/ident/stability_barrier.hpp).
#include "tricot/ident/stability_barrier.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/core/format.hpp"
#include "tricot/fem/response_surface.hpp"
#include "tricot/fem/wrinkling.hpp"

namespace tricot::ident {

namespace {

void check(bool ok, const char* field, double got, const std::string& expected) {
  if (!ok)
    throw InputError(Location{"", 0, std::string("stability.") + field}, "out of range", format_number(got), expected);
}

}  // namespace

void StabilityBarrierOptions::validate() const {
  check(std::isfinite(eC_min) && eC_min > -0.5, "eC_min", eC_min, "> -0.5 (a Green–Lagrange strain)");
  check(std::isfinite(eW_min) && eW_min > -0.5, "eW_min", eW_min, "> -0.5 (a Green–Lagrange strain)");
  check(std::isfinite(eC_max) && eC_max > eC_min, "eC_max", eC_max, "> eC_min");
  check(std::isfinite(eW_max) && eW_max > eW_min, "eW_max", eW_max, "> eW_min");
  check(step > 0 && (eC_max - eC_min) / step < 1e4 && (eW_max - eW_min) / step < 1e4, "step", step,
        "> 0, at most 10^4 points per axis");
  // The margins' open ends at 0 first, so that the message says so.
  check(det_margin > 0, "det_margin", det_margin, "> 0");
  check(slope_margin > 0, "slope_margin", slope_margin, "> 0");
  check(taut_stress > 0, "taut_stress", taut_stress, "> 0");
  check_ranges(*this);
}

StabilizedObjective::StabilizedObjective(const Objective& objective, StabilityBarrierOptions options)
    : objective_(objective), options_(options) {
  options_.validate();
  Eigen::VectorXd J(objective.parameters().size());
  for (Eigen::Index k = 0; k < J.size(); ++k) J(k) = objective.parameters()[k].start;
  const std::unique_ptr<fem::Law> law = objective.law_at(J);
  // A tension-field wrapper keeps the response surface's force–strain map: the barrier is on it.
  const auto* rs = dynamic_cast<const fem::ResponseSurface*>(&fem::unwrapped(*law));
  if (!rs)
    throw InputError(Location{"", 0, "law.type"}, "the stability barrier needs a response surface", law->name(),
                     "response_surface");
  base_ = rs->coefficients();
  const auto names = rs->coefficient_names();
  for (int k = 0; k < objective.law_parameters(); ++k)  // the force scales after them have no barrier
    coefficient_.push_back(static_cast<int>(
        std::find(names.begin(), names.end(), objective.parameters()[static_cast<std::size_t>(k)].name) -
        names.begin()));
  const int nx = static_cast<int>(std::floor((options_.eC_max - options_.eC_min) / options_.step + 1e-9)) + 1;
  const int ny = static_cast<int>(std::floor((options_.eW_max - options_.eW_min) / options_.step + 1e-9)) + 1;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      grid_.emplace_back(options_.eC_min + i * options_.step, options_.eW_min + j * options_.step);
  // A_i = ∂(F_C, F_W)/∂ε of the law with coefficient i alone at 1: central differences of a C¹
  // piecewise polynomial (truncation O(h²) away from 0, O(h) on the compression kink at 0).
  constexpr double h = 1e-7;
  fem::ResponseSurface unit = *rs;
  basis_.assign(grid_.size(), std::vector<Mat2>(static_cast<std::size_t>(base_.size())));
  for (Eigen::Index i = 0; i < base_.size(); ++i) {
    unit.set_coefficients(Eigen::VectorXd::Unit(base_.size(), i));
    for (std::size_t g = 0; g < grid_.size(); ++g) {
      const double eC = grid_[g](0), eW = grid_[g](1);
      Mat2 A;
      A.col(0) = (unit.forces(eC + h, eW) - unit.forces(eC - h, eW)) / (2 * h);
      A.col(1) = (unit.forces(eC, eW + h) - unit.forces(eC, eW - h)) / (2 * h);
      basis_[g][static_cast<std::size_t>(i)] = A;
    }
  }
  if (options_.acoustic_margin > 0) {
    // The plane-stress law at F = diag(λC, λW) in its material axes, with each coefficient alone.
    tangent_.assign(grid_.size(), std::vector<Mat4>(static_cast<std::size_t>(base_.size()) + 1));
    stress_.assign(grid_.size(), std::vector<Mat2>(static_cast<std::size_t>(base_.size()) + 1));
    fem::LawOutput out;
    for (Eigen::Index i = -1; i < base_.size(); ++i) {
      unit.set_coefficients(i < 0 ? Eigen::VectorXd(Eigen::VectorXd::Zero(base_.size()))
                                  : Eigen::VectorXd(Eigen::VectorXd::Unit(base_.size(), i)));
      const std::size_t k = static_cast<std::size_t>(i + 1);
      for (std::size_t g = 0; g < grid_.size(); ++g) {
        const Mat2 F = Vec2(std::sqrt(1 + 2 * grid_[g](0)), std::sqrt(1 + 2 * grid_[g](1))).asDiagonal();
        unit.evaluate({F, Mat2::Identity()}, {true, false}, out);
        tangent_[g][k] = i < 0 ? out.A : Mat4(out.A - tangent_[g][0]);
        stress_[g][k] = i < 0 ? Mat2(out.P * F.transpose()) : Mat2(out.P * F.transpose() - stress_[g][0]);
      }
    }
  }
}

namespace {

/// λ_min of sym M and its unit eigenvector.
std::pair<double, Vec2> lowest(const Mat2& M) {
  const Eigen::SelfAdjointEigenSolver<Mat2> eig(0.5 * (M + M.transpose()));
  return {eig.eigenvalues()(0), eig.eigenvectors().col(0)};
}

/// min over 36 directions (every 5°) of λ_min(sym Q(N)): an upper bound of a_min, cheap (the barrier is
/// evaluated at every bisection of LM's step cut, theory/fabric.md §3.2).
double sampled_ellipticity(const Mat4& A) {
  static const std::array<Vec2, 36> directions = [] {
    std::array<Vec2, 36> d;
    for (std::size_t a = 0; a < d.size(); ++a) {
      const double t = double(a) * std::numbers::pi / 36;
      d[a] = Vec2(std::cos(t), std::sin(t));
    }
    return d;
  }();
  double best = INFINITY;
  for (const Vec2& N : directions) {
    const Mat2 Q = fem::acoustic_tensor(A, N);
    const double q01 = 0.5 * (Q(0, 1) + Q(1, 0));
    best = std::min(best, 0.5 * (Q(0, 0) + Q(1, 1)) - std::hypot(0.5 * (Q(0, 0) - Q(1, 1)), q01));
  }
  return best;
}

}  // namespace

void StabilizedObjective::add_ellipticity(const Eigen::VectorXd& c, Eigen::VectorXd& r,
                                          Eigen::MatrixXd* jacobian) const {
  const double w = options_.weight, ma = options_.acoustic_margin, s0 = options_.taut_stress;
  const Eigen::Index first = 3 * static_cast<Eigen::Index>(grid_.size());
  for (std::size_t g = 0; g < grid_.size(); ++g) {
    Mat4 A = tangent_[g][0];
    Mat2 S = stress_[g][0];
    for (Eigen::Index i = 0; i < c.size(); ++i) {
      A += c(i) * tangent_[g][static_cast<std::size_t>(i + 1)];
      S += c(i) * stress_[g][static_cast<std::size_t>(i + 1)];
    }
    const auto [sigma, v_s] = lowest(S);
    // The gate: smoothstep 3x² − 2x³ of x = clamp(σ_min/σ₀, 0, 1), C¹ at both ends (a grid point may
    // sit exactly at σ_min = 0, where a law's force vanishes).
    const double x = std::clamp(sigma / s0, 0.0, 1.0);
    const double gate = x * x * (3 - 2 * x);
    if (!(gate > 0)) continue;
    // Refined only where the samples come within 2 m_a (5° samples of a λ_min made of harmonics of 2t
    // and 4t miss its minimum by far less than m_a): most of the grid is far from it.
    if (sampled_ellipticity(A) >= 2 * ma) continue;
    const fem::Ellipticity e = fem::strong_ellipticity(A);
    const double shortfall = ma - e.min_eigenvalue;
    if (!(shortfall > 0)) continue;
    const Eigen::Index row = first + static_cast<Eigen::Index>(g);
    r(row) = w * gate * shortfall / ma;
    if (!jacobian) continue;
    // ∂a_min/∂c_i = vᵀ sym Q_i(N*) v at the minimising N* and λ_min's eigenvector v (envelope); ∂σ_min/∂c_i
    // likewise with S_i.
    const double t = e.angle_deg * std::numbers::pi / 180;
    const Vec2 N(std::cos(t), std::sin(t));
    const Vec2 v_a = lowest(fem::acoustic_tensor(A, N)).second;
    const double gate_slope = 6 * x * (1 - x) / s0;
    for (std::size_t k = 0; k < coefficient_.size(); ++k) {
      const std::size_t i = static_cast<std::size_t>(coefficient_[k]) + 1;
      const double da = v_a.dot(fem::acoustic_tensor(tangent_[g][i], N) * v_a);
      const double ds = v_s.dot(stress_[g][i] * v_s);
      (*jacobian)(row, static_cast<Eigen::Index>(k)) = w * (gate_slope * ds * shortfall - gate * da) / ma;
    }
  }
}

Eigen::VectorXd StabilizedObjective::law_coefficients(const Eigen::VectorXd& J) const {
  Eigen::VectorXd c = base_;
  for (std::size_t k = 0; k < coefficient_.size(); ++k) c(coefficient_[k]) = J(static_cast<Eigen::Index>(k));
  return c;
}

std::vector<Mat2> StabilizedObjective::force_jacobians(const Eigen::VectorXd& J) const {
  const Eigen::VectorXd c = law_coefficients(J);
  std::vector<Mat2> out(grid_.size(), Mat2::Zero());
  for (std::size_t g = 0; g < grid_.size(); ++g)
    for (Eigen::Index i = 0; i < c.size(); ++i) out[g] += c(i) * basis_[g][static_cast<std::size_t>(i)];
  return out;
}

Eigen::VectorXd StabilizedObjective::barrier(const Eigen::VectorXd& J, Eigen::MatrixXd* jacobian) const {
  const std::vector<Mat2> A = force_jacobians(J);
  const Eigen::Index n = J.size();
  Eigen::VectorXd r = Eigen::VectorXd::Zero(barrier_rows());
  if (jacobian) jacobian->setZero(barrier_rows(), n);
  const double w = options_.weight, ms = options_.slope_margin, md = options_.det_margin;
  for (std::size_t g = 0; g < grid_.size(); ++g) {
    const Mat2& a = A[g];
    const Eigen::Index row = 3 * static_cast<Eigen::Index>(g);
    const double values[3] = {a(0, 0) - ms, a(1, 1) - ms, a.determinant() - md};
    const double margins[3] = {ms, ms, md};
    for (int m = 0; m < 3; ++m) {
      if (values[m] >= 0) continue;
      r(row + m) = -w * values[m] / margins[m];
      if (!jacobian) continue;
      for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(coefficient_.size()); ++k) {
        const Mat2& b = basis_[g][static_cast<std::size_t>(coefficient_[static_cast<std::size_t>(k)])];
        // ∂A11/∂J_k = b11, ∂A22/∂J_k = b22, ∂det A/∂J_k = b11 a22 + a11 b22 − b12 a21 − a12 b21.
        const double d = m == 0   ? b(0, 0)
                         : m == 1 ? b(1, 1)
                                  : b(0, 0) * a(1, 1) + a(0, 0) * b(1, 1) - b(0, 1) * a(1, 0) - a(0, 1) * b(1, 0);
        (*jacobian)(row + m, k) = -w * d / margins[m];
      }
    }
  }
  if (options_.acoustic_margin > 0) add_ellipticity(law_coefficients(J), r, jacobian);
  return r;
}

Evaluation StabilizedObjective::evaluate(const Eigen::VectorXd& J, bool jacobian) const {
  Evaluation e = objective_.evaluate(J, jacobian);
  if (!e.ok) return e;
  Eigen::MatrixXd Jb;
  const Eigen::VectorXd rb = barrier(J, jacobian ? &Jb : nullptr);
  const Eigen::Index m = e.r.size(), rows = m + rb.size();
  Eigen::VectorXd r(rows), y(rows);
  r << e.r, rb;
  y.head(std::min(m, e.y.size())) = e.y.head(std::min(m, e.y.size()));
  y.tail(rows - std::min(m, e.y.size())).setZero();
  y.tail(rb.size()) = rb;
  e.r = std::move(r);
  e.y = std::move(y);
  if (jacobian && e.jacobian.size() > 0) {
    Eigen::MatrixXd full(rows, e.jacobian.cols());
    full.topRows(m) = e.jacobian;
    full.bottomRows(rb.size()) = Jb;
    e.jacobian = std::move(full);
  }
  return e;
}

Eigen::VectorXd StabilizedObjective::residual_variance() const {
  const Eigen::VectorXd v = objective_.residual_variance();
  if (v.size() == 0) return v;
  Eigen::VectorXd out = Eigen::VectorXd::Ones(v.size() + barrier_rows());
  out.head(v.size()) = v;
  return out;
}

}  // namespace tricot::ident
