// Orthotropic response-surface fabric law (see response_surface.hpp, docs/theory.md §5).
#include "tricot/fem/response_surface.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "fabric_frame.hpp"
#include "invalid_state.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

double ipow(double x, int n) {
  double r = 1;
  for (int i = 0; i < n; ++i) r *= x;
  return r;
}

/// One factor x^n of a monomial and its derivative, extended to compression [choice]
/// (docs/theory/fabric.md §3.1): for x < 0 a power n ≥ 2 vanishes (linear and almansi); x^1 stays x
/// (linear, and always for the other force's strain, `own` false) or, for the force's own strain,
/// becomes the Euler–Almansi strain x/(1 + 2x) = (1 − λ⁻²)/2 (almansi): slope 1 at 0 (C¹), −∞ as
/// the fibre's stretch λ → 0. The law stays linear in its coefficients.
struct Factor {
  double v, d;
};
Factor factor(double x, int n, ResponseSurface::Compression mode, bool own) {
  if (n == 0) return {1.0, 0.0};
  if (x < 0 && mode != ResponseSurface::Compression::polynomial) {
    if (n >= 2) return {0.0, 0.0};
    if (own && mode == ResponseSurface::Compression::almansi) {
      const double s = 1 + 2 * x;  // λ² > 0 whenever det F > 0
      if (!(s > 0)) return {NAN, NAN};
      return {x / s, 1 / (s * s)};
    }
  }
  return {ipow(x, n), n * ipow(x, n - 1)};
}

/// The factors x^0 … x^n_max of one strain, as the force's own strain and as the other force's
/// (they differ only for x < 0 at n = 1): `factor` for every n, by the same products as ipow.
constexpr int kTabled = 16;  // exponents below this come from the table; higher ones from `factor`
struct Powers {
  Factor own[kTabled], other[kTabled];
  int n = 0;  // tabled up to n
};
void fill_powers(double x, int n_max, ResponseSurface::Compression mode, Powers& t) {
  t.n = std::min(n_max, kTabled - 1);
  t.own[0] = t.other[0] = {1.0, 0.0};
  double p = 1;  // x^(k−1)
  for (int k = 1; k <= t.n; ++k) {
    if (x < 0 && mode != ResponseSurface::Compression::polynomial) {
      t.own[k] = factor(x, k, mode, true);
      t.other[k] = factor(x, k, mode, false);
    } else {
      // Member by member: `own[k] = other[k] = {…}` stored other[k] in two halves and reloaded it whole
      // for own[k], a store-forwarding stall that was ~2/3 of this function.
      const double v = p * x, d = k * p;
      t.own[k].v = t.other[k].v = v;
      t.own[k].d = t.other[k].d = d;
    }
    p *= x;
  }
}

/// εC^p εW^q (each factor extended as in `factor`; `force` 0 = course, whose own strain is εC, 1 =
/// wale) and its two partial derivatives.
struct MonomialValue {
  double v, d_C, d_W;
};
MonomialValue eval(const Monomial& m, double eC, double eW, ResponseSurface::Compression mode, int force) {
  const Factor C = factor(eC, m.p, mode, force == 0), W = factor(eW, m.q, mode, force == 1);
  return {C.v * W.v, C.d * W.v, C.v * W.d};
}
/// The same from the strains' tables.
MonomialValue eval(const Monomial& m, const Powers& tC, const Powers& tW, double eC, double eW,
                   ResponseSurface::Compression mode, int force) {
  if (m.p > tC.n || m.q > tW.n) return eval(m, eC, eW, mode, force);
  const Factor C = force == 0 ? tC.own[m.p] : tC.other[m.p], W = force == 1 ? tW.own[m.q] : tW.other[m.q];
  return {C.v * W.v, C.d * W.v, C.v * W.d};
}

void check_monomials(const std::vector<Monomial>& list, const char* force) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Monomial& m = list[i];
    const std::string got = std::string(force) + " monomial (" + std::to_string(m.p) + ", " + std::to_string(m.q) + ")";
    if (m.p < 0 || m.q < 0 || m.p + m.q == 0)
      throw InputError(Location{"", 0, std::string("law.response_surface.") + force}, "bad exponents", got,
                       "p >= 0, q >= 0, p + q >= 1");
    if (std::find(list.begin(), list.begin() + i, m) != list.begin() + i)
      throw InputError(Location{"", 0, std::string("law.response_surface.") + force}, "repeated monomial", got,
                       "each (p, q) once per force");
  }
}

std::vector<std::string> general_names(const std::vector<Monomial>& course, const std::vector<Monomial>& wale) {
  std::vector<std::string> names;
  for (const Monomial& m : course) names.push_back("C_" + std::to_string(m.p) + "_" + std::to_string(m.q));
  for (const Monomial& m : wale) names.push_back("W_" + std::to_string(m.p) + "_" + std::to_string(m.q));
  return names;
}

}  // namespace

ResponseSurface::ResponseSurface(std::vector<Monomial> course, std::vector<Monomial> wale, double G_s,
                                 std::vector<std::string> names)
    : course_(std::move(course)), wale_(std::move(wale)), names_(std::move(names)), G_s_(G_s) {
  check_monomials(course_, "course");
  check_monomials(wale_, "wale");
  if (!(G_s > 0) || !std::isfinite(G_s))
    throw InputError(Location{"", 0, "law.response_surface.shear_stiffness"}, "out of range", std::to_string(G_s),
                     "> 0 N/mm");
  c_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(course_.size() + wale_.size()));
  for (const auto* list : {&course_, &wale_})
    for (const Monomial& m : *list) max_p_ = std::max(max_p_, m.p), max_q_ = std::max(max_q_, m.q);
}

ResponseSurface::ResponseSurface(std::vector<Monomial> course, std::vector<Monomial> wale, double G_s,
                                 const Eigen::VectorXd& c)
    : ResponseSurface(course, wale, G_s, general_names(course, wale)) {
  if (c.size() != 0) set_coefficients(c);
}

ResponseSurface ResponseSurface::separable(int nC, int mC, int nW, int mW, double G_s) {
  if (nC < 0 || mC < 0 || nW < 0 || mW < 0)
    throw InputError(
        Location{"", 0, "law.response_surface.orders"}, "negative polynomial order",
        std::to_string(nC) + ", " + std::to_string(mC) + ", " + std::to_string(nW) + ", " + std::to_string(mW), ">= 0");
  std::vector<Monomial> course, wale;
  std::vector<std::string> names;
  for (int i = 1; i <= nC; ++i) course.push_back({i, 0}), names.push_back("a" + std::to_string(i));
  for (int j = 1; j <= mC; ++j) course.push_back({0, j}), names.push_back("b" + std::to_string(j));
  for (int i = 1; i <= nW; ++i) wale.push_back({0, i}), names.push_back("c" + std::to_string(i));
  for (int j = 1; j <= mW; ++j) wale.push_back({j, 0}), names.push_back("d" + std::to_string(j));
  return ResponseSurface(std::move(course), std::move(wale), G_s, std::move(names));
}

ResponseSurface ResponseSurface::preset(const std::string& name, double G_s) {
  if (name == "paper14") return separable(6, 2, 4, 2, G_s);
  if (name == "paper24") return separable(6, 6, 6, 6, G_s);
  throw InputError(Location{"", 0, "law.response_surface.preset"}, "unknown response-surface preset", name,
                   "paper14, paper24");
}

void ResponseSurface::set_coefficients(const Eigen::VectorXd& c) {
  if (c.size() != c_.size())
    throw InputError(Location{"", 0, "law.response_surface.coefficients"},
                     "wrong number of response-surface coefficients", std::to_string(c.size()),
                     std::to_string(c_.size()));
  if (!c.allFinite())
    throw InputError(Location{"", 0, "law.response_surface.coefficients"}, "not a finite number", "", "finite N/mm");
  c_ = c;
}

Vec2 ResponseSurface::forces(double eps_C, double eps_W) const {
  Vec2 f = Vec2::Zero();
  const std::size_t nc = course_.size();
  for (std::size_t k = 0; k < nc; ++k) f(0) += c_(k) * eval(course_[k], eps_C, eps_W, compression_, 0).v;
  for (std::size_t k = 0; k < wale_.size(); ++k) f(1) += c_(nc + k) * eval(wale_[k], eps_C, eps_W, compression_, 1).v;
  return f;
}

Mat2 ResponseSurface::material_frame_stress(const LawInput& in) const {
  const detail::FabricKinematics k = detail::fabric_kinematics(in, false);
  const Vec2 f = forces(k.E_m(0, 0), k.E_m(1, 1));
  return detail::fabric_T({f(0), f(1)}, G_s_, k.E_m);
}

void ResponseSurface::evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const {
  if (detail::invalid_state(in.F.determinant(), req, c_.size(), out)) return;
  const detail::FabricKinematics k = detail::fabric_kinematics(in, req.tangent);
  const double eC = k.E_m(0, 0), eW = k.E_m(1, 1);
  Powers tC, tW;
  fill_powers(eC, max_p_, compression_, tC);
  fill_powers(eW, max_q_, compression_, tW);
  detail::FabricForces f;
  const std::size_t nc = course_.size();
  for (std::size_t i = 0; i < nc; ++i) {
    const MonomialValue m = eval(course_[i], tC, tW, eC, eW, compression_, 0);
    f.F_C += c_(i) * m.v;
    f.dFC_deC += c_(i) * m.d_C;
    f.dFC_deW += c_(i) * m.d_W;
  }
  for (std::size_t i = 0; i < wale_.size(); ++i) {
    const MonomialValue m = eval(wale_[i], tC, tW, eC, eW, compression_, 1);
    f.F_W += c_(nc + i) * m.v;
    f.dFW_deC += c_(nc + i) * m.d_C;
    f.dFW_deW += c_(nc + i) * m.d_W;
  }
  detail::fabric_stress(in, k, f, G_s_, req.tangent, out);
  if (req.sensitivities) {
    // Linear: ∂P/∂c_k = R Q T_k Qᵀ with T_k = diag(monomial, 0) (course) or diag(0, monomial) (wale),
    // i.e. the monomial times R Q diag(1, 0) Qᵀ or R Q diag(0, 1) Qᵀ.
    const Mat2 B_C = detail::fabric_basis(in, k, Vec2(1, 0).asDiagonal());
    const Mat2 B_W = detail::fabric_basis(in, k, Vec2(0, 1).asDiagonal());
    out.dP_dc.resize(c_.size());
    for (std::size_t i = 0; i < nc; ++i) out.dP_dc[i] = eval(course_[i], tC, tW, eC, eW, compression_, 0).v * B_C;
    for (std::size_t i = 0; i < wale_.size(); ++i)
      out.dP_dc[nc + i] = eval(wale_[i], tC, tW, eC, eW, compression_, 1).v * B_W;
  } else {
    out.dP_dc.clear();
  }
}

}  // namespace tricot::fem
