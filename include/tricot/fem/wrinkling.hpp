// A tension-field (wrinkling) membrane around any plane-stress law (docs/theory/fabric.md §8).
//
// A membrane has no bending stiffness: where one principal stress would be compressive it buckles
// out of its plane into fine wrinkles and carries a uniaxial tension along them instead. The
// wrapper keeps the in-plane F of the FE (the wrinkles' mean surface) and gives the inner law the
// deformation of the wavy sheet itself (Roddeman-type modified deformation gradient):
//   F̃ = (I + β n ⊗ n) F = F + (s − ℓ) n ⊗ m,
// n across the wrinkles (current configuration), m = Fᵀn / ℓ the same direction in the reference one,
// ℓ = |Fᵀn| the current stretch across and s = (1 + β) ℓ the wavy sheet's: β ≥ 0 is the extra
// stretch across the wrinkles that the waves take up. The unknowns are s and m's angle φ (n ∝ cof(F) m):
// unlike n's angle they stay well scaled where the FE squeezes an element flat (det F → 0). They solve
// the two conditions that the traction on a cut along the wrinkles vanishes (its normal and its shear
// part), for any law, isotropic or orthotropic, with or without a potential:
//   g(s, φ) = P(F̃) m = 0     (ℓ g = P(F̃) Fᵀ n ∝ σ̃ n, σ̃ the inner law's Cauchy stress at F̃).
// The membrane force of the mean surface is then P = P(F̃): across a cut along the wrinkles it is
// zero, and along them it is the wavy sheet's force (its extra length (1 + β) cancels the smaller
// current length of the cut). For a law with a potential W this is ∂W_relaxed/∂F of the relaxed
// energy W_relaxed(F) = W(F̃).
//
// Three states, from S = P(F) Fᵀ (the inner law's Kirchhoff stress, up to R):
// - taut:      det S > 0 and tr S > 0 (both principal stresses tensile): the law as it is (but see
//              the smoothed switch below);
// - wrinkled:  otherwise, where g = 0 has a root with β ≥ 0 and a positive tension tᵀ P(F̃) F̃ᵀ t
//              along the wrinkles (t = (−sin θ, cos θ));
// - slack:     otherwise: no stress.
// P is continuous at both switches (β = 0 at taut/wrinkled, zero tension at wrinkled/slack).
// Smoothed switch [choice]: the wrinkle strain used is a C¹ ramp r(β) of width w
// (WrinklingOptions::smoothing), so that the tangent is continuous across the taut/wrinkled switch;
// the root β is then also solved on the taut side, where it is negative, within −w.
//
// Residual stiffness [choice]: wrinkled and slack membranes have no stiffness across the wrinkles
// (the FE tangent is singular there: a slack patch floats). The wrapper returns
//   P = (1 − η) P_relaxed(F) + η P_inner(F)
// with the documented fraction η = WrinklingOptions::residual_stiffness (default 1e-3): η of the
// inner law's own stiffness and stress are kept in every state (exactly the inner law when taut),
// so P stays continuous and A consistent.
//
// A = ∂P/∂F and ∂P/∂c are exact: the wrinkle stretch and direction are differentiated implicitly,
// ∂z/∂F = −(∂g/∂z)⁻¹ ∂g/∂F and ∂z/∂c = −(∂g/∂z)⁻¹ ∂g/∂c, z = (s, φ). The relaxed law is not linear
// in the inner law's coefficients (z depends on them): linear_in_coefficients() is false and dP_dc
// carries the implicit term.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tricot/core/options.hpp"
#include "tricot/fem/law.hpp"

namespace tricot::fem {

/// Options of WrinklingLaw.
struct WrinklingOptions {
  /// η: the fraction of the inner law kept in every state (the slack membrane's stiffness and the
  /// stiffness across wrinkles, as a fraction of the taut law's), in [0, 0.5). 0 = the pure tension
  /// field (a slack patch then has a singular tangent). Default 1e-3.
  double residual_stiffness = 1e-3;
  /// w: width of the smoothed taut/wrinkled switch, in wrinkle strain, in [0, 0.1]. The wrinkle
  /// strain used is r(β), a C¹ ramp: 0 for β ≤ −w, (β + w)²/(4w) between, β above w, where β is the
  /// zero-traction root (negative on the taut side near the switch). 0 = the sharp switch, whose
  /// tangent jumps; the FE's Newton then chatters where a whole region sits on the switch (a sheet
  /// stretched one way with no stress across, as in the rig's first increments). Default 1e-3.
  double smoothing = 1e-3;
  /// Newton on (s, φ) stops when |P(F̃) m| ≤ tolerance × |P(F)| (relative), in (0, 1e-6]. Default 1e-13.
  double tolerance = 1e-13;
  /// Newton iterations on (s, φ), 1–200. Default 50.
  int max_iterations = 50;

  /// The config keys of [law] these options hold (core/options.hpp; tolerance and max_iterations are
  /// set in code). `law.` is the law's table: [law], or a [[law.region]] of its own.
  static auto keys() {
    using O = WrinklingOptions;
    return std::tuple{
        option(&O::residual_stiffness, "law.residual_stiffness",
               "With wrinkling: the fraction η of the law kept in every state, so that wrinkled and slack\n"
               "points keep a small stiffness across the wrinkles (P = (1 − η) P_relaxed + η P_law), in\n"
               "[0, 0.5).",
               0, 0.5),
        option(&O::smoothing, "law.wrinkle_smoothing",
               "With wrinkling: the width w (in wrinkle strain) of the smoothed taut/wrinkled switch, a C¹\n"
               "ramp that keeps the FE tangent continuous where a region sits on the switch; 0 = sharp.\n"
               "In [0, 0.1].",
               0, 0.1)};
  }
  /// Throws InputError (key `law.<field>`, or `law.wrinkle_<field>` for tolerance and max_iterations)
  /// for a value out of range.
  void validate() const;
};

/// The state of the membrane at one point.
enum class MembraneState { taut = 0, wrinkled = 1, slack = 2 };
const char* to_string(MembraneState s);

/// The relaxed state at one point: which of the three, and for a wrinkled one the wrinkles.
struct WrinkleState {
  MembraneState state = MembraneState::taut;
  /// Wrinkle strain r(β) ≥ 0 (WrinklingOptions::smoothing): the extra stretch across the wrinkles
  /// that the waves take up (0 unless wrinkled).
  double beta = 0;
  /// The zero-traction root β itself (> −w; may be below 0 within the smoothed switch).
  double root_beta = 0;
  /// Angle from x of the wrinkles (the tension direction t, current configuration), radians in
  /// (−π/2, π/2]; 0 unless wrinkled.
  double angle = 0;
  /// The wavy sheet's stretch across the wrinkles, s = (1 + β) |Fᵀ n| (0 unless wrinkled).
  double stretch = 0;
  /// Angle from x of the direction across the wrinkles in the reference configuration, m = Fᵀn / |Fᵀn|
  /// (radians; 0 unless wrinkled). With `stretch`, the unknowns of the wrinkle solve.
  double reference_angle = 0;
  /// Tension along the wrinkles, tᵀ P(F̃) F̃ᵀ t [N/mm · stretch]; 0 unless wrinkled.
  double tension = 0;
  /// Newton iterations the wrinkle solve took (0 when taut).
  int iterations = 0;
};

class WrinklingLaw : public Law {
 public:
  /// Wraps a clone of `inner`. Validates `options` (InputError).
  explicit WrinklingLaw(const Law& inner, WrinklingOptions options = {});
  WrinklingLaw(const WrinklingLaw& other);
  WrinklingLaw& operator=(const WrinklingLaw& other);

  /// The inner law's name: reports and truth files name the material, not the wrapper.
  std::string name() const override { return inner_->name(); }
  std::vector<std::string> coefficient_names() const override { return inner_->coefficient_names(); }
  Eigen::VectorXd coefficients() const override { return inner_->coefficients(); }
  void set_coefficients(const Eigen::VectorXd& c) override { inner_->set_coefficients(c); }
  /// false: the wrinkle angle and strain depend on the coefficients (dP_dc is still exact).
  bool linear_in_coefficients() const override { return false; }
  /// det F ≤ 0 gives NaN outputs (the solver reports an invalid state), as the inner law does.
  void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const override;
  std::unique_ptr<Law> clone() const override { return std::make_unique<WrinklingLaw>(*this); }

  /// The state at `in` (what evaluate() uses).
  WrinkleState state(const LawInput& in) const;
  const Law& inner() const { return *inner_; }
  const WrinklingOptions& options() const { return options_; }

 private:
  /// The relaxed state and, when wrinkled, the inner law's output at F̃ (tangent always; the
  /// sensitivities when asked).
  WrinkleState solve(const LawInput& in, const LawOutput& at_F, bool sensitivities, LawOutput& at_Ft) const;

  std::unique_ptr<Law> inner_;
  WrinklingOptions options_;
};

/// The law itself when it is not a WrinklingLaw, else its inner law.
const Law& unwrapped(const Law& law);

struct Mesh;

/// The wrinkles of one element: the area fractions of its integration points that are wrinkled and
/// slack, and the wrinkles' mean direction (radians from x, current configuration; the doubled-angle
/// mean, so that t and −t agree; 0 where nothing wrinkles).
struct ElementWrinkles {
  double wrinkled = 0, slack = 0, angle = 0;
};
/// Per element of `mesh` under displacements `u`, material axes at `material_angle_deg`: its
/// wrinkles under `law`, all zero when the law is no WrinklingLaw (or an element is inverted).
std::vector<ElementWrinkles> element_wrinkles(const Mesh& mesh, const Law& law, double material_angle_deg,
                                              const Eigen::VectorXd& u);
/// The area fractions of the whole mesh that are wrinkled and slack.
Vec2 wrinkled_and_slack_area(const Mesh& mesh, const std::vector<ElementWrinkles>& wrinkles);

}  // namespace tricot::fem
