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

/// The wrinkle kinematics at z = (β, θ): n across the wrinkles, t along them, M = I + β n nᵀ,
/// F̃ = M F and its partial derivatives ∂F̃/∂β = n nᵀ F, ∂F̃/∂θ = β (t nᵀ + n tᵀ) F (flattened).
struct Wrinkle {
  Vec2 n, t;
  Mat2 M, Ft;
  Eigen::Matrix<double, 4, 2> Ft_z;
};

Wrinkle wrinkle(const Mat2& F, double beta, double theta) {
  Wrinkle w;
  w.n = Vec2(std::cos(theta), std::sin(theta));
  w.t = Vec2(-w.n(1), w.n(0));
  const Mat2 nn = w.n * w.n.transpose();
  w.M = Mat2::Identity() + beta * nn;
  w.Ft = w.M * F;
  w.Ft_z.col(0) = flatten(nn * F);
  w.Ft_z.col(1) = flatten(beta * (w.t * w.n.transpose() + w.n * w.t.transpose()) * F);
  return w;
}

/// g = P(F̃) Fᵀ n: the traction on a cut along the wrinkles (∝ σ̃ n).
Vec2 residual(const Mat2& F, const Wrinkle& w, const LawOutput& at_Ft) { return at_Ft.P * (F.transpose() * w.n); }

/// ∂g/∂z (2 × 2): dP̃ = A ∂F̃/∂z; the θ column adds P̃ Fᵀ t from ∂n/∂θ = t.
Mat2 residual_z(const Mat2& F, const Wrinkle& w, const LawOutput& at_Ft) {
  const Vec2 Fn = F.transpose() * w.n;
  Mat2 G;
  for (int m = 0; m < 2; ++m) G.col(m) = unflatten(Vec4(at_Ft.A * w.Ft_z.col(m))) * Fn;
  G.col(1) += at_Ft.P * (F.transpose() * w.t);
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
  check(residual_stiffness >= 0 && residual_stiffness < 0.5, "residual_stiffness", residual_stiffness, "[0, 0.5)");
  check(tolerance > 0 && tolerance <= 1e-6, "wrinkle_tolerance", tolerance, "(0, 1e-6]");
  check(smoothing >= 0 && smoothing <= 0.1, "wrinkle_smoothing", smoothing, "[0, 0.1]");
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

WrinkleState WrinklingLaw::solve(const LawInput& in, const LawOutput& at_F, bool sensitivities, LawOutput& at_Ft) const {
  const Mat2& F = in.F;
  WrinkleState st;
  // Taut: both principal values of S = P Fᵀ tensile (det S > 0, tr S > 0), or S at rest to round-off
  // of the stiffness (the unstressed state is the corner of all three states: the taut tangent there
  // lets the FE leave it in any direction). With a smoothed switch (width w > 0), a taut point whose
  // zero-traction root β (< 0: the sheet would have to shorten across) may lie above −w is solved
  // too: the linear estimate β ≈ −λ_min(sym S) / (∂(nᵀ g)/∂β) at β = 0 decides.
  const Mat2 S = at_F.P * F.transpose();
  const double scale_S = max_abs(at_F.A) * max_abs(F) * max_abs(F);
  const double width = options_.smoothing;
  Eigen::SelfAdjointEigenSolver<Mat2> eig_S(0.5 * (S + S.transpose()));
  const Vec2 nS = eig_S.eigenvectors().col(0);
  const double theta_S = std::atan2(nS(1), nS(0));
  double beta_start = 0;
  if ((S.determinant() > 0 && S.trace() > 0) || max_abs(S) <= 1e-12 * scale_S) {
    if (!(width > 0) || max_abs(S) <= 1e-12 * scale_S) return st;
    const Wrinkle w0 = wrinkle(F, 0, theta_S);
    const double k = nS.dot(residual_z(F, w0, at_F).col(0));
    if (!(k > 0)) return st;
    beta_start = -eig_S.eigenvalues()(0) / k;
    if (beta_start <= -2 * width) return st;
  }

  // Wrinkled or slack: Newton on z = (β, θ) for g = 0. Two starts: β = 0 with n along the most
  // compressive principal direction of sym S (exact at the taut/wrinkled switch), then n along the
  // least stretched principal direction of B = F Fᵀ with 1 + β = 1/√b_min (exact at the
  // wrinkled/slack switch, where F̃ is a rotation and θ is otherwise ill-conditioned; and for
  // isotropic laws the direction is exact everywhere).
  const LawRequest with_tangent{true, false};
  const double scale = at_F.P.norm() * F.norm() + 1e-300;
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
  auto newton = [&](Vec2 z) {
    Run run;
    Wrinkle w = wrinkle(F, z(0), z(1));
    LawOutput at;
    inner_->evaluate({w.Ft, in.Q, in.region}, with_tangent, at);
    Vec2 g = residual(F, w, at);
    int it = 0;
    for (; it < options_.max_iterations; ++it) {
      if (!g.allFinite()) break;
      if (g.norm() <= options_.tolerance * scale) {
        run.converged = true;
        // One more full step to round-off (cheap at quadratic rate): P(F̃) is then exact to round-off
        // of P̃, not of the larger P(F) of the tolerance's scale.
        const Eigen::FullPivLU<Mat2> lu(residual_z(F, w, at));
        if (lu.isInvertible()) {
          const Vec2 zt = z - lu.solve(g);
          const Wrinkle wt = wrinkle(F, zt(0), zt(1));
          LawOutput trial;
          inner_->evaluate({wt.Ft, in.Q, in.region}, with_tangent, trial);
          const Vec2 gt = residual(F, wt, trial);
          if (gt.allFinite() && gt.norm() <= g.norm()) z = zt, w = wt, at = std::move(trial), g = gt;
        }
        break;
      }
      const Eigen::FullPivLU<Mat2> lu(residual_z(F, w, at));
      if (!lu.isInvertible()) break;
      const Vec2 dz = -lu.solve(g);
      // Backtracking on |g|: keep β in (−1/2, beta_max) and take the first step that lowers |g| (the
      // full step near the root: quadratic convergence).
      double a = 1;
      bool accepted = false;
      for (int b = 0; b < 30 && !accepted; ++b, a *= 0.5) {
        const Vec2 zt = z + a * dz;
        if (!(zt(0) > -0.5 && zt(0) < beta_max)) continue;
        const Wrinkle wt = wrinkle(F, zt(0), zt(1));
        LawOutput trial;
        inner_->evaluate({wt.Ft, in.Q, in.region}, with_tangent, trial);
        const Vec2 gt = residual(F, wt, trial);
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
  // A root counts when it is a tension field: β above the ramp's foot and a positive tension along
  // t. The rotated root (n and t swapped, a negative "tension") and a root missed from one start send
  // the solve to the next start; slack only when no start finds a tension field.
  auto tension_of = [](const Run& r) { return r.w.t.dot(r.at_Ft.P * r.w.Ft.transpose() * r.w.t); };
  auto is_field = [&](const Run& r) {
    return r.converged && smooth_ramp(r.z(0), width)(0) > 0 && (width > 0 || r.z(0) >= -1e-10) && tension_of(r) > 0;
  };
  const Vec2 starts[3] = {Vec2(beta_start, theta_S),
                          Vec2(b_min < 1 ? 1 / std::sqrt(b_min) - 1 : std::max(beta_start, 0.0), std::atan2(nB(1), nB(0))),
                          Vec2(std::max(beta_start, 0.0), theta_S + std::numbers::pi / 2)};
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
    if (run.converged && !(smooth_ramp(run.z(0), width)(0) > 0) && tension_of(run) > 0) below_foot = true;
  }
  st.iterations = it;
  if (found) {
    const Vec2& z = run.z;
    const Wrinkle& w = run.w;
    at_Ft = std::move(run.at_Ft);
    st.state = MembraneState::wrinkled;
    st.root_beta = z(0);
    st.beta = smooth_ramp(z(0), width)(0);
    st.angle = wrap_angle(z(1) + std::numbers::pi / 2);
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
  // Wrinkled: P = (1 − η) P(F̃_eff) + η P(F), F̃_eff = M(r(β), θ) F; the implicit derivatives of
  // z = (β, θ) with g(F, z) = 0 at the root, through the ramp r.
  const Mat2& F = in.F;
  const double theta = st.angle - std::numbers::pi / 2;
  const Wrinkle w = wrinkle(F, st.root_beta, theta);  // the root (at_Ft is the inner law there)
  const Mat2 G_z = residual_z(F, w, at_Ft);
  const Eigen::FullPivLU<Mat2> lu(G_z);
  const Vec2 Fn = F.transpose() * w.n;
  const double slope = smooth_ramp(st.root_beta, options_.smoothing)(1);
  const bool at_root = st.beta == st.root_beta;
  const Wrinkle we = at_root ? w : wrinkle(F, st.beta, theta);  // the effective wavy sheet
  LawOutput at_eff;
  if (!at_root) inner_->evaluate({we.Ft, in.Q, in.region}, {true, req.sensitivities}, at_eff);
  const LawOutput& eff = at_root ? at_Ft : at_eff;
  out.P = (1 - eta) * eff.P + eta * out.P;
  out.lambda3 = eff.lambda3;
  // ∂P̃_eff/∂z through the ramp: the β column times r'(β).
  Eigen::Matrix<double, 4, 2> A_z = eff.A * we.Ft_z;
  A_z.col(0) *= slope;
  if (req.tangent) {
    // ∂F̃/∂F at fixed z: δF̃ = M δF, i.e. D(2a + b, 2k + l) = M(a, k) δ(b, l) (M at the root for g,
    // M_eff for P).
    auto dFt_dF = [](const Mat2& M) {
      Mat4 D = Mat4::Zero();
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int k = 0; k < 2; ++k) D(2 * a + b, 2 * k + b) = M(a, k);
      return D;
    };
    const Mat4 A_F_root = at_Ft.A * dFt_dF(w.M);
    // ∂g/∂F: dP̃ Fᵀ n + P̃ δFᵀ n; δF = e_k e_lᵀ gives δFᵀ n = n_k e_l.
    Eigen::Matrix<double, 2, 4> G_F;
    for (int k = 0; k < 2; ++k)
      for (int l = 0; l < 2; ++l) {
        const int c = 2 * k + l;
        G_F.col(c) = unflatten(Vec4(A_F_root.col(c))) * Fn + w.n(k) * at_Ft.P.col(l);
      }
    const Eigen::Matrix<double, 2, 4> z_F = -lu.solve(G_F);
    const Mat4 A_F_eff = at_root ? A_F_root : Mat4(eff.A * dFt_dF(we.M));
    out.A = (1 - eta) * (A_F_eff + A_z * z_F) + eta * out.A;
  }
  if (req.sensitivities) {
    for (std::size_t k = 0; k < nc; ++k) {
      const Vec2 z_c = -lu.solve(Vec2(at_Ft.dP_dc[k] * Fn));
      out.dP_dc[k] = (1 - eta) * (eff.dP_dc[k] + unflatten(Vec4(A_z * z_c))) + eta * out.dP_dc[k];
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
