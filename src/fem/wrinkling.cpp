// Tension-field membrane around any plane-stress law (see wrinkling.hpp, docs/theory/fabric.md §8).
#include "tricot/fem/wrinkling.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "invalid_state.hpp"
#include "tricot/fem/element.hpp"
#include "tricot/fem/mesh.hpp"
#include "tricot/core/error.hpp"
#include "tricot/core/format.hpp"

namespace tricot::fem {

namespace {

void check(bool ok, const char* field, double got, const std::string& expected) {
  if (!ok) throw InputError(Location{"", 0, std::string("law.") + field}, "out of range", format_number(got), expected);
}

/// The wrinkle kinematics (docs/theory/fabric.md §8): m = (cos φ, sin φ) across the wrinkles in the
/// reference configuration, n ∝ cof(F) m across them in the current one (so Fᵀ n = ℓ m, ℓ the
/// current stretch across, det F / |cof(F) m|), t ⊥ n along them, and the wavy sheet
///   F̃ = F + q n mᵀ,
/// q the extra length across that the waves take up (q = s − ℓ at the wavy sheet's stretch s).
/// Parametrised by the reference direction φ, not by n's angle: where the FE squeezes an element to
/// nearly nothing across (det F → 0), F̃ depends on n's angle through q |Fᵀ t|, beyond what a double
/// resolves, and on φ at O(1). dn_dF and dn_dphi: n's turn along t per δF (flattened row by row) and
/// per δφ; dell_dF and dell_dphi: ℓ's partials.
struct Wrinkle {
  Vec2 m, mp, n, t;
  double ell = 0, q = 0, dn_dphi = 0, dell_dphi = 0;
  Vec4 dn_dF, dell_dF;
  Mat2 Ft;
};

/// The wavy sheet at reference direction φ with the wrinkle stretch s across (q = s − ℓ), or with
/// the extra length q itself (`is_stretch` false).
Wrinkle wrinkle(const Mat2& F, double phi, double s_or_q, bool is_stretch = true) {
  Wrinkle w;
  w.m = Vec2(std::cos(phi), std::sin(phi));
  w.mp = Vec2(-w.m(1), w.m(0));
  Mat2 C;  // cof(F) = det F F⁻ᵀ, linear in F
  C << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
  const Vec2 c = C * w.m;
  const double c_norm = c.norm();
  w.n = c / c_norm;
  w.t = Vec2(-w.n(1), w.n(0));
  w.ell = F.determinant() / c_norm;
  w.q = is_stretch ? s_or_q - w.ell : s_or_q;
  w.Ft = F + w.q * w.n * w.m.transpose();
  // δc turns n along t by tᵀδc / |c|, and moves ℓ = nᵀ F m by that times tᵀ F m (+ nᵀ δF m;
  // nᵀ F δm = ℓ mᵀ δm = 0). δF = e_k e_lᵀ: cof(δF) = ±e_(1−k) e_(1−l)ᵀ (+ on the diagonal).
  const double tFm = w.t.dot(F * w.m);
  w.dn_dphi = w.t.dot(C * w.mp) / c_norm;
  w.dell_dphi = w.dn_dphi * tFm;
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l) {
      const int i = 2 * k + l;
      w.dn_dF(i) = (k == l ? 1.0 : -1.0) * w.m(1 - l) * w.t(1 - k) / c_norm;
      w.dell_dF(i) = w.dn_dF(i) * tFm + w.n(k) * w.m(l);
    }
  return w;
}

/// F̃'s derivatives (flattened) when q is a function of the stretch s and of ℓ, dq = dq_ds ds + dq_dell dℓ:
/// ∂F̃/∂F (4 × 4) and ∂F̃/∂z (4 × 2), z = (s, φ). At the root q = s − ℓ: dq_ds = 1, dq_dell = −1.
struct WrinkleJacobian {
  Mat4 dFt_dF;
  Eigen::Matrix<double, 4, 2> dFt_dz;
};

WrinkleJacobian jacobian(const Wrinkle& w, double dq_ds = 1, double dq_dell = -1) {
  const Vec4 tm = flatten(w.t * w.m.transpose()), nm = flatten(w.n * w.m.transpose());
  WrinkleJacobian J;
  J.dFt_dF = Mat4::Identity() + w.q * tm * w.dn_dF.transpose() + dq_dell * nm * w.dell_dF.transpose();
  J.dFt_dz.col(0) = dq_ds * nm;
  J.dFt_dz.col(1) = w.q * (w.dn_dphi * tm + flatten(w.n * w.mp.transpose())) + dq_dell * w.dell_dphi * nm;
  return J;
}

/// g = P(F̃) m: the traction on a cut along the wrinkles (ℓ g = P(F̃) Fᵀ n, ∝ σ̃ n).
Vec2 residual(const Wrinkle& w, const LawOutput& at_Ft) { return at_Ft.P * w.m; }

/// ∂g/∂z (2 × 2) at the root: dP̃ = A ∂F̃/∂z; the φ column adds P̃ ∂m/∂φ.
Mat2 dg_dz(const Wrinkle& w, const LawOutput& at_Ft) {
  const Eigen::Matrix<double, 4, 2> dFt_dz = jacobian(w).dFt_dz;
  Mat2 G;
  for (int j = 0; j < 2; ++j) G.col(j) = unflatten(Vec4(at_Ft.A * dFt_dz.col(j))) * w.m;
  G.col(1) += at_Ft.P * w.mp;
  return G;
}

/// max |x_ij| by a plain loop (Eigen's vectorised cwiseAbs().maxCoeff() on a 4 × 4 trips GCC 12's
/// -Wuninitialized inside the AVX-512 intrinsics).
template <class M>
double max_abs(const M& m) {
  double r = 0;
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) r = std::max(r, std::abs(m(i, j)));
  return r;
}

/// The largest wrinkle stretch 1 + β, as a multiple of the one that makes the wavy sheet as long as
/// at rest across its most compressed direction (1/√b_min, b_min the least eigenvalue of B = F Fᵀ;
/// at least 1): waves that take up 10 times that. Beyond it a law whose force decays with stretch
/// (P = R τ̂ U⁻¹ of a log-strain law) has |g| → 0 at β → ∞, a root at infinity that Newton would
/// walk to. Relative, not absolute: a fixed cap (β < 10) cut off the roots of a sheet squeezed to
/// less than 1/11 of its length across (a slack corner of the rig), whose state then flipped between
/// wrinkled at the cap and slack, a jump in P that stalled the FE's Newton.
constexpr double kWaveFactor = 10;

/// The C¹ ramp r(β) of width w and its slope: 0 for β ≤ −w, (β + w)²/(4w) between, β for β ≥ w
/// (max(β, 0) when w = 0).
Vec2 smooth_ramp(double beta, double w) {
  if (beta >= w) return {beta, 1.0};
  if (beta <= -w) return {0.0, 0.0};
  return {(beta + w) * (beta + w) / (4 * w), (beta + w) / (2 * w)};
}

double wrap_angle(double a) {
  constexpr double pi = std::numbers::pi;
  a = std::fmod(a, pi);
  if (a <= -pi / 2) a += pi;
  if (a > pi / 2) a -= pi;
  return a;
}

}  // namespace

void WrinklingOptions::validate() const {
  check_ranges(*this);
  // The declared range includes its ends; η's excludes 0.5.
  check(residual_stiffness < 0.5, "residual_stiffness", residual_stiffness, "[0, 0.5)");
  check(tolerance > 0 && tolerance <= 1e-6, "wrinkle_tolerance", tolerance, "(0, 1e-6]");
  check(max_iterations >= 1 && max_iterations <= 200, "wrinkle_max_iterations", max_iterations, "1 to 200");
}

const char* to_string(MembraneState s) {
  switch (s) {
    case MembraneState::taut: return "taut";
    case MembraneState::wrinkled: return "wrinkled";
    case MembraneState::slack: return "slack";
  }
  return "?";
}

WrinklingLaw::WrinklingLaw(const Law& inner, WrinklingOptions options)
    : inner_(unwrapped(inner).clone()), options_(options) {
  options_.validate();
}

WrinklingLaw::WrinklingLaw(const WrinklingLaw& other) : inner_(other.inner_->clone()), options_(other.options_) {}

WrinklingLaw& WrinklingLaw::operator=(const WrinklingLaw& other) {
  if (this != &other) inner_ = other.inner_->clone(), options_ = other.options_;
  return *this;
}

const Law& unwrapped(const Law& law) {
  const auto* w = dynamic_cast<const WrinklingLaw*>(&law);
  return w ? w->inner() : law;
}

WrinkleState WrinklingLaw::solve(const LawInput& in, const LawOutput& at_F, bool sensitivities,
                                 LawOutput& at_Ft) const {
  const Mat2& F = in.F;
  WrinkleState st;
  // Taut: both principal values of S = P Fᵀ tensile (det S > 0, tr S > 0), or S at rest to round-off
  // of the stiffness (the unstressed state is the corner of all three states: the taut tangent there
  // lets the FE leave it in any direction). With a smoothed switch (width w > 0), a taut point whose
  // zero-traction root β (< 0: the sheet would have to shorten across) may lie above −w is solved
  // too: the linear estimate β ≈ −λ_min(sym S) / (∂(nᵀ P(F̃) Fᵀ n)/∂β) at β = 0 decides
  // (∂F̃/∂β = n nᵀ F there).
  const Mat2 S = at_F.P * F.transpose();
  const double scale_S = max_abs(at_F.A) * max_abs(F) * max_abs(F);
  const double width = options_.smoothing;
  Eigen::SelfAdjointEigenSolver<Mat2> eig_S(0.5 * (S + S.transpose()));
  const Vec2 nS = eig_S.eigenvectors().col(0);
  double beta_start = 0;
  if ((S.determinant() > 0 && S.trace() > 0) || max_abs(S) <= 1e-12 * scale_S) {
    if (!(width > 0) || max_abs(S) <= 1e-12 * scale_S) return st;
    const Vec2 Fn = F.transpose() * nS;
    const double k = nS.dot(unflatten(Vec4(at_F.A * flatten(nS * Fn.transpose()))) * Fn);
    if (!(k > 0)) return st;
    beta_start = -eig_S.eigenvalues()(0) / k;
    if (beta_start <= -2 * width) return st;
  }

  // Wrinkled or slack: Newton on z = (s, φ) for g = 0. Three starts, each a direction n across and a
  // wrinkle strain β (z from m = Fᵀn / |Fᵀn|, s = (1 + β) |Fᵀn|): β = 0 with n along the most
  // compressive principal direction of sym S (exact at the taut/wrinkled switch); n along the least
  // stretched principal direction of B = F Fᵀ with 1 + β = 1/√b_min, i.e. s = 1 (exact at the
  // wrinkled/slack switch, where F̃ is a rotation and φ is otherwise ill-conditioned; and for
  // isotropic laws the direction is exact everywhere); then n along t of the first.
  const LawRequest with_tangent{true, false};
  const double scale = at_F.P.norm() + 1e-300;
  struct Run {
    bool converged = false;
    Vec2 z;
    Wrinkle w;
    LawOutput at_Ft;
    int iterations = 0;
  };
  Eigen::SelfAdjointEigenSolver<Mat2> eig_B(F * F.transpose());
  const Vec2 nB = eig_B.eigenvectors().col(0);
  const double b_min = eig_B.eigenvalues()(0);
  const double beta_max = kWaveFactor * std::max(1.0, 1 / std::sqrt(b_min)) - 1;
  auto evaluate_at = [&](const Vec2& z, Wrinkle& w, LawOutput& at) {
    w = wrinkle(F, z(1), z(0));
    inner_->evaluate({w.Ft, in.Q, in.region}, with_tangent, at);
    return residual(w, at);
  };
  auto newton = [&](Vec2 z) {
    Run run;
    Wrinkle w;
    LawOutput at;
    Vec2 g = evaluate_at(z, w, at);
    int it = 0;
    for (; it < options_.max_iterations; ++it) {
      if (!g.allFinite()) break;
      if (g.norm() <= options_.tolerance * scale) {
        run.converged = true;
        // One more full step to round-off (cheap at quadratic rate): P(F̃) is then exact to round-off
        // of P̃, not of the larger P(F) of the tolerance's scale.
        const Eigen::FullPivLU<Mat2> lu(dg_dz(w, at));
        if (lu.isInvertible()) {
          const Vec2 zt = z - lu.solve(g);
          Wrinkle wt;
          LawOutput trial;
          const Vec2 gt = evaluate_at(zt, wt, trial);
          if (gt.allFinite() && gt.norm() <= g.norm()) z = zt, w = wt, at = std::move(trial), g = gt;
        }
        break;
      }
      const Eigen::FullPivLU<Mat2> lu(dg_dz(w, at));
      if (!lu.isInvertible()) break;
      const Vec2 dz = -lu.solve(g);
      // Backtracking on |g|: keep β = q/ℓ in (−1/2, beta_max) and take the first step that lowers |g|
      // (the full step near the root: quadratic convergence).
      double a = 1;
      bool accepted = false;
      for (int b = 0; b < 30 && !accepted; ++b, a *= 0.5) {
        const Vec2 zt = z + a * dz;
        const Wrinkle wt = wrinkle(F, zt(1), zt(0));
        if (!(wt.q / wt.ell > -0.5 && wt.q / wt.ell < beta_max)) continue;
        LawOutput trial;
        inner_->evaluate({wt.Ft, in.Q, in.region}, with_tangent, trial);
        const Vec2 gt = residual(wt, trial);
        if (gt.allFinite() && gt.norm() < g.norm()) {
          z = zt, w = wt, at = std::move(trial), g = gt;
          accepted = true;
        }
      }
      if (!accepted) {
        // No decrease: at the round-off floor of g the root is found; otherwise the start failed.
        run.converged = g.norm() <= 1e3 * options_.tolerance * scale;
        break;
      }
    }
    run.z = z, run.w = w, run.at_Ft = std::move(at), run.iterations = it;
    return run;
  };
  auto start = [&](const Vec2& n, double beta) {
    const Vec2 a = F.transpose() * n;
    return Vec2((1 + beta) * a.norm(), std::atan2(a(1), a(0)));
  };
  // A root counts when it is a tension field: β above the ramp's foot and a positive tension along
  // t. The rotated root (n and t swapped, a negative "tension") and a root missed from one start send
  // the solve to the next start; slack only when no start finds a tension field.
  auto beta_of = [](const Run& r) { return r.w.q / r.w.ell; };
  auto tension_of = [](const Run& r) { return r.w.t.dot(r.at_Ft.P * r.w.Ft.transpose() * r.w.t); };
  auto is_field = [&](const Run& r) {
    return r.converged && smooth_ramp(beta_of(r), width)(0) > 0 && (width > 0 || beta_of(r) >= -1e-10) &&
           tension_of(r) > 0;
  };
  const Vec2 starts[3] = {start(nS, beta_start),
                          start(nB, b_min < 1 ? 1 / std::sqrt(b_min) - 1 : std::max(beta_start, 0.0)),
                          start(Vec2(-nS(1), nS(0)), std::max(beta_start, 0.0))};
  Run run;
  int it = 0;
  bool found = false, below_foot = false;
  for (const Vec2& z0 : starts) {
    run = newton(z0);
    it += run.iterations;
    if (is_field(run)) {
      found = true;
      break;
    }
    if (run.converged && !(smooth_ramp(beta_of(run), width)(0) > 0) && tension_of(run) > 0) below_foot = true;
  }
  st.iterations = it;
  if (found) {
    const Wrinkle& w = run.w;
    at_Ft = std::move(run.at_Ft);
    st.state = MembraneState::wrinkled;
    st.stretch = run.z(0);
    st.reference_angle = run.z(1);
    st.root_beta = beta_of(run);
    st.beta = smooth_ramp(st.root_beta, width)(0);
    st.angle = wrap_angle(std::atan2(w.t(1), w.t(0)));
    st.tension = w.t.dot(at_Ft.P * w.Ft.transpose() * w.t);
    if (sensitivities) inner_->evaluate({w.Ft, in.Q, in.region}, {true, true}, at_Ft);
  } else if (beta_start != 0 || below_foot) {
    st.state = MembraneState::taut;  // a taut-side root below the ramp's foot (or none found there)
  } else {
    st.state = MembraneState::slack;
  }
  return st;
}

WrinkleState WrinklingLaw::state(const LawInput& in) const {
  LawOutput at_F, at_Ft;
  if (!(in.F.determinant() > 0) || !in.F.allFinite()) return {MembraneState::slack, 0, 0, 0, 0, 0};
  inner_->evaluate(in, {true, false}, at_F);
  return solve(in, at_F, false, at_Ft);
}

void WrinklingLaw::evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const {
  const std::size_t nc = static_cast<std::size_t>(inner_->coefficients().size());
  if (detail::invalid_state(in.F.determinant(), req, nc, out)) return;
  // The inner law at F: the taut answer, the state test (which needs its tangent's scale) and the
  // residual part η P(F).
  inner_->evaluate(in, {true, req.sensitivities}, out);
  LawOutput at_Ft;
  const WrinkleState st = solve(in, out, req.sensitivities, at_Ft);
  if (st.state == MembraneState::taut) return;
  const double eta = options_.residual_stiffness;
  if (st.state == MembraneState::slack) {
    out.P *= eta;
    if (req.tangent) out.A *= eta;
    for (Mat2& d : out.dP_dc) d *= eta;
    return;
  }
  // Wrinkled: P = (1 − η) P(F̃_eff) + η P(F), F̃_eff = F + q_eff n mᵀ with q_eff = ℓ r(β), β = s/ℓ − 1;
  // the implicit derivatives of z = (s, φ) with g(F, z) = 0 at the root, through the ramp r
  // (dq_eff = r' ds + (r − r' (1 + β)) dℓ).
  const Mat2& F = in.F;
  const Wrinkle w = wrinkle(F, st.reference_angle, st.stretch);  // the root (at_Ft is the inner law there)
  const Eigen::FullPivLU<Mat2> lu(dg_dz(w, at_Ft));
  const bool at_root = st.beta == st.root_beta;
  const Vec2 ramp = smooth_ramp(st.root_beta, options_.smoothing);
  const Wrinkle we = at_root ? w : wrinkle(F, st.reference_angle, w.ell * ramp(0), false);  // the effective sheet
  LawOutput at_eff;
  if (!at_root) inner_->evaluate({we.Ft, in.Q, in.region}, {true, req.sensitivities}, at_eff);
  const LawOutput& eff = at_root ? at_Ft : at_eff;
  out.P = (1 - eta) * eff.P + eta * out.P;
  out.lambda3 = eff.lambda3;
  const WrinkleJacobian J_eff = at_root ? jacobian(w) : jacobian(we, ramp(1), ramp(0) - ramp(1) * (1 + st.root_beta));
  const Eigen::Matrix<double, 4, 2> dP_dz = eff.A * J_eff.dFt_dz;
  if (req.tangent) {
    // ∂g/∂F = (A ∂F̃/∂F) m at the root.
    const Mat4 dP_dF_root = at_Ft.A * jacobian(w).dFt_dF;
    Eigen::Matrix<double, 2, 4> dg_dF;
    for (int c = 0; c < 4; ++c) dg_dF.col(c) = unflatten(Vec4(dP_dF_root.col(c))) * w.m;
    const Eigen::Matrix<double, 2, 4> dz_dF = -lu.solve(dg_dF);
    const Mat4 dP_dF_eff = at_root ? dP_dF_root : Mat4(eff.A * J_eff.dFt_dF);
    out.A = (1 - eta) * (dP_dF_eff + dP_dz * dz_dF) + eta * out.A;
  }
  if (req.sensitivities) {
    for (std::size_t k = 0; k < nc; ++k) {
      const Vec2 dz_dc = -lu.solve(Vec2(at_Ft.dP_dc[k] * w.m));
      out.dP_dc[k] = (1 - eta) * (eff.dP_dc[k] + unflatten(Vec4(dP_dz * dz_dc))) + eta * out.dP_dc[k];
    }
  }
}

std::vector<ElementWrinkles> element_wrinkles(const Mesh& mesh, const Law& law, double material_angle_deg,
                                              const Eigen::VectorXd& u) {
  std::vector<ElementWrinkles> out(static_cast<std::size_t>(mesh.elements()));
  const auto* wrinkling = dynamic_cast<const WrinklingLaw*>(&law);
  if (!wrinkling) return out;
  const Mat2 Q = material_axes(material_angle_deg);
  for (int e = 0; e < mesh.elements(); ++e) {
    const ElementGeometry geo = element_geometry(mesh, e);
    const ElementVector ue = element_displacements(mesh, e, u);
    double area = 0, wrinkled = 0, slack = 0, c2 = 0, s2 = 0;
    for (int q = 0; q < geo.points; ++q) {
      const double w = geo.dA0[q];
      area += w;
      const Mat2 F = deformation_gradient(geo, q, ue);
      if (!(F.determinant() > 0)) continue;
      const WrinkleState st = wrinkling->state({F, Q, geo.region});
      if (st.state == MembraneState::wrinkled) {
        wrinkled += w;
        c2 += w * std::cos(2 * st.angle), s2 += w * std::sin(2 * st.angle);
      } else if (st.state == MembraneState::slack) {
        slack += w;
      }
    }
    ElementWrinkles& r = out[static_cast<std::size_t>(e)];
    r.wrinkled = wrinkled / area, r.slack = slack / area;
    r.angle = wrinkled > 0 ? 0.5 * std::atan2(s2, c2) : 0.0;
  }
  return out;
}

Vec2 wrinkled_and_slack_area(const Mesh& mesh, const std::vector<ElementWrinkles>& wrinkles) {
  double area = 0, wrinkled = 0, slack = 0;
  for (int e = 0; e < mesh.elements() && e < static_cast<int>(wrinkles.size()); ++e) {
    const ElementGeometry geo = element_geometry(mesh, e);
    double a = 0;
    for (int q = 0; q < geo.points; ++q) a += geo.dA0[q];
    area += a, wrinkled += a * wrinkles[static_cast<std::size_t>(e)].wrinkled,
        slack += a * wrinkles[static_cast<std::size_t>(e)].slack;
  }
  return area > 0 ? Vec2(wrinkled / area, slack / area) : Vec2::Zero();
}

}  // namespace tricot::fem
