// Compressible Mooney–Rivlin membrane (see compressible_mooney_rivlin.hpp, docs/theory.md §5.2).
#include "tricot/fem/compressible_mooney_rivlin.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "invalid_state.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

// A value with its gradient and Hessian in v = (C11, C12, C22, C33) (C12 = C21 counted once): the
// chain rule of the strain energy through the invariants, by hand, in closed form.
struct Jet {
  double v = 0;
  Eigen::Vector4d g = Eigen::Vector4d::Zero();
  Eigen::Matrix4d h = Eigen::Matrix4d::Zero();
};
Jet operator+(const Jet& a, const Jet& b) { return {a.v + b.v, a.g + b.g, a.h + b.h}; }
Jet operator*(double s, const Jet& a) { return {s * a.v, s * a.g, s * a.h}; }
Jet operator*(const Jet& a, const Jet& b) {
  return {a.v * b.v, a.v * b.g + b.v * a.g, a.v * b.h + b.v * a.h + a.g * b.g.transpose() + b.g * a.g.transpose()};
}
// f(a) from f, f′, f″ at a.v.
Jet apply(const Jet& a, double f, double df, double d2f) {
  return {f, df * a.g, df * a.h + d2f * a.g * a.g.transpose()};
}
Jet power(const Jet& a, double p) {
  return apply(a, std::pow(a.v, p), p * std::pow(a.v, p - 1), p * (p - 1) * std::pow(a.v, p - 2));
}
Jet integer_power(const Jet& a, int n) {  // exact at a = 0 (the reference state), unlike pow(a, n − 2)
  auto p = [&](int m) {
    double r = 1;
    for (int k = 0; k < m; ++k) r *= a.v;
    return r;
  };
  return apply(a, p(n), n >= 1 ? n * p(n - 1) : 0.0, n >= 2 ? n * (n - 1) * p(n - 2) : 0.0);
}

// Ī1 − 3, Ī2 − 3 and ln J as jets of v.
struct Invariants {
  Jet x1, x2, lnJ;
};
Invariants invariants(double a, double b, double c, double t) {
  Jet I1{a + c + t, {1, 0, 1, 1}, Eigen::Matrix4d::Zero()};
  Jet I2{a * c - b * b + t * (a + c), {c + t, -2 * b, a + t, a + c}, Eigen::Matrix4d::Zero()};
  I2.h(0, 2) = I2.h(2, 0) = 1, I2.h(1, 1) = -2, I2.h(0, 3) = I2.h(3, 0) = 1, I2.h(2, 3) = I2.h(3, 2) = 1;
  Jet I3{t * (a * c - b * b), {t * c, -2 * t * b, t * a, a * c - b * b}, Eigen::Matrix4d::Zero()};
  I3.h(0, 2) = I3.h(2, 0) = t, I3.h(1, 1) = -2 * t, I3.h(0, 3) = I3.h(3, 0) = c, I3.h(2, 3) = I3.h(3, 2) = a;
  I3.h(1, 3) = I3.h(3, 1) = -2 * b;
  Invariants r;
  r.x1 = I1 * power(I3, -1.0 / 3) + Jet{-3.0};
  r.x2 = I2 * power(I3, -2.0 / 3) + Jet{-3.0};
  r.lnJ = apply(I3, 0.5 * std::log(I3.v), 0.5 / I3.v, -0.5 / (I3.v * I3.v));
  return r;
}

// The energy's basis: one jet per coefficient (each term with C = 1, then ½ (ln J)²).
std::vector<Jet> basis(const std::vector<MooneyRivlinTerm>& terms, const Invariants& x) {
  std::vector<Jet> w;
  for (const MooneyRivlinTerm& t : terms) w.push_back(integer_power(x.x1, t.i) * integer_power(x.x2, t.j));
  w.push_back(0.5 * (x.lnJ * x.lnJ));
  return w;
}

Jet energy(const std::vector<Jet>& w, const Eigen::VectorXd& c) {
  Jet W;
  for (size_t k = 0; k < w.size(); ++k) W = W + c(static_cast<Eigen::Index>(k)) * w[k];
  return W;
}

// S₂ = 2 ∂W/∂C₂ from the gradient in v: S11 = 2 g0, S12 = g1, S22 = 2 g2.
Mat2 in_plane_stress(const Eigen::Vector4d& g) {
  Mat2 S;
  S << 2 * g(0), g(1), g(1), 2 * g(2);
  return S;
}

int var(int M, int J) { return M == J ? 2 * M : 1; }  // C_MJ → index in v

}  // namespace

CompressibleMooneyRivlin::CompressibleMooneyRivlin(std::vector<MooneyRivlinTerm> terms, double kappa,
                                                   Kinematics kinematics)
    : terms_(std::move(terms)), kappa_(kappa), kinematics_(kinematics) {
  MooneyRivlin check(terms_);  // the terms' own checks (law.mooney_rivlin.terms, .values)
  if (!(kappa > 0) || !std::isfinite(kappa))
    throw InputError(Location{"", 0, "law.mooney_rivlin.kappa"}, "out of range", std::to_string(kappa), "> 0 N/mm");
}

std::vector<std::string> CompressibleMooneyRivlin::coefficient_names() const {
  std::vector<std::string> n = MooneyRivlin(terms_).coefficient_names();
  n.push_back("kappa");
  return n;
}

Eigen::VectorXd CompressibleMooneyRivlin::coefficients() const {
  Eigen::VectorXd c(static_cast<Eigen::Index>(terms_.size()) + 1);
  for (size_t k = 0; k < terms_.size(); ++k) c(static_cast<Eigen::Index>(k)) = terms_[k].C;
  c(c.size() - 1) = kappa_;
  return c;
}

void CompressibleMooneyRivlin::set_coefficients(const Eigen::VectorXd& c) {
  if (c.size() != static_cast<Eigen::Index>(terms_.size()) + 1)
    throw InputError(Location{"", 0, "law.mooney_rivlin"}, "wrong number of Mooney–Rivlin coefficients",
                     std::to_string(c.size()), std::to_string(terms_.size() + 1));
  std::vector<MooneyRivlinTerm> t = terms_;
  for (size_t k = 0; k < t.size(); ++k) t[k].C = c(static_cast<Eigen::Index>(k));
  *this = CompressibleMooneyRivlin(std::move(t), c(c.size() - 1), kinematics_);
}

void CompressibleMooneyRivlin::evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const {
  const Mat2& F = in.F;
  const size_t n = terms_.size() + 1;
  if (detail::invalid_state(F.determinant(), req, n, out)) return;
  const Mat2 C2 = F.transpose() * F;
  const Eigen::VectorXd c = coefficients();
  // C33: 1 in plane strain; in plane stress the root of ∂W/∂C33 = 0 by Newton in s = ln C33 from the
  // incompressible guess 1/det C₂ (W is convex in s at fixed C₂ near it).
  double t = 1;
  Invariants x = invariants(C2(0, 0), C2(0, 1), C2(1, 1), t);
  std::vector<Jet> w = basis(terms_, x);
  Jet W = energy(w, c);
  if (kinematics_ == Kinematics::plane_stress) {
    double s = -std::log(C2.determinant());
    for (int it = 0; it < 60; ++it) {
      t = std::exp(s);
      x = invariants(C2(0, 0), C2(0, 1), C2(1, 1), t);
      w = basis(terms_, x);
      W = energy(w, c);
      const double g = W.g(3) * t, dg = W.h(3, 3) * t * t + W.g(3) * t;  // d/ds of ∂W/∂t · t
      const double ds = -g / dg;
      s += std::isfinite(ds) ? std::clamp(ds, -1.0, 1.0) : 0.0;
      if (!(std::abs(ds) > 1e-14)) break;
    }
  }
  out.P = F * in_plane_stress(W.g);
  out.lambda3 = std::sqrt(t);
  // Condensed Hessian in (C11, C12, C22): plane stress eliminates C33 through ∂W/∂C33 = 0.
  Eigen::Matrix3d H = W.h.topLeftCorner<3, 3>();
  Eigen::Vector3d h3 = W.h.block<3, 1>(0, 3);
  const bool condense = kinematics_ == Kinematics::plane_stress;
  if (condense) H -= h3 * h3.transpose() / W.h(3, 3);
  if (req.tangent) {
    // dS_MJ/dC_NL = f_MJ f′_NL H(v(MJ), v(NL)) with S_MJ = f_MJ g, f = 2 on the diagonal, 1 off it, and
    // f′ = ½ off the diagonal (C12 and C21 both move with v1). A_iJkL = δ_ik S_LJ + 2 F_iM F_kN D_MJNL.
    const Mat2 S = in_plane_stress(W.g);
    auto D = [&](int M, int J, int N, int L) {
      return (M == J ? 2.0 : 1.0) * (N == L ? 1.0 : 0.5) * H(var(M, J), var(N, L));
    };
    for (int i = 0; i < 2; ++i)
      for (int J = 0; J < 2; ++J)
        for (int k = 0; k < 2; ++k)
          for (int L = 0; L < 2; ++L) {
            double a = i == k ? S(L, J) : 0.0;
            for (int M = 0; M < 2; ++M)
              for (int N = 0; N < 2; ++N) a += 2 * F(i, M) * F(k, N) * D(M, J, N, L);
            out.A(2 * i + J, 2 * k + L) = a;
          }
  }
  out.dP_dc.clear();
  if (req.sensitivities)
    for (size_t k = 0; k < n; ++k) {
      // ∂S/∂c_k at fixed C33, plus (plane stress) the move of C33: dt/dc_k = −∂g_t/∂c_k / ∂g_t/∂t.
      Eigen::Vector4d g = w[k].g;
      if (condense) g.head<3>() -= h3 * (w[k].g(3) / W.h(3, 3));
      out.dP_dc.push_back(F * in_plane_stress(g));
    }
}

}  // namespace tricot::fem
