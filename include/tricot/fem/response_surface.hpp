// Orthotropic response-surface fabric law (docs/theory.md §5 eqs. 8/10 [choice]; docs/theory/fabric.md §3).
//
// Forces per unit reference width along course and wale are polynomials of the Green–Lagrange
// strains along the material axes (a_C = Q.col(0), a_W = Q.col(1) in the reference configuration):
//   E = ½(FᵀF − I),  E_m = Qᵀ E Q,  εC = a_C·E·a_C = E_m11,  εW = a_W·E·a_W = E_m22,  E_CW = E_m12,
//   F_C = Σ_k C_k εC^p_k εW^q_k,   F_W = Σ_k W_k εC^p_k εW^q_k   (one monomial list per force),
//   T = [[F_C, 2 G_s E_CW], [2 G_s E_CW, F_W]]   (nominal forces in the corotated material frame),
//   P = R Q T Qᵀ   (F = R U; the material frame turns with R).
// With the axes aligned (Q = I) and F = diag(λ1, λ2) (R = I), P = diag(F_C, F_W) exactly: P11 is the
// force per unit reference width along course. G_s [N/mm] is a small fixed shear stiffness (not
// identified). P is linear in the coefficients, so ∂P/∂c_k = R Q T_k Qᵀ is exact. A = ∂P/∂F is exact
// (needs ∂R/∂F) and in general not major-symmetric (the law is not derived from a potential).
// λ3 = 1/det F (incompressible knit; reported only).
//
// Compression [choice] (docs/theory/fabric.md §3.1): a knit carries little compression, and a
// polynomial fitted to tension extrapolates wildly below 0 (a free strip near the clips of the rig is
// compressed to εW ≈ −0.38 while no test measures there). By default (Compression::almansi) every
// factor x^n with n ≥ 2 of a monomial is replaced by 0 for x < 0, and the first power of the force's
// own strain (εC in F_C, εW in F_W) by the Euler–Almansi strain x/(1 + 2x) (the other strain's first
// power stays linear): the law is C¹ at 0, still linear in its coefficients (∂P/∂c exact), and its
// force grows without bound as a fibre is compressed toward zero length, so a free strip cannot
// collapse, while the cross couplings stay bounded (the compressed tangent is diagonally dominant).
// Compression::linear keeps x^1 (a finite force at λ → 0: a strip whose transverse coupling exceeds
// half its own-direction stiffness has no equilibrium and inverts); Compression::polynomial keeps the
// plain polynomial everywhere.
//
// Coefficient names, in the order of coefficients():
//   separable / presets (docs/theory.md §5):
//     F_C = Σ_{i=1..nC} a_i εC^i + Σ_{j=1..mC} b_j εW^j,   F_W = Σ_{i=1..nW} c_i εW^i + Σ_{j=1..mW} d_j εC^j,
//     names "a1".."a{nC}", "b1".."b{mC}", "c1".."c{nW}", "d1".."d{mW}" (units N/mm);
//   general: "C_p_q" for the course monomial εC^p εW^q, then "W_p_q" for the wale ones.
#pragma once

#include <string>
#include <vector>

#include "tricot/fem/law.hpp"

namespace tricot::fem {

/// εC^p εW^q with p, q ≥ 0 and p + q ≥ 1 (no constant term: no force at rest).
struct Monomial {
  int p = 0;
  int q = 0;
  bool operator==(const Monomial&) const = default;
};

class ResponseSurface : public Law {
 public:
  /// How the monomials extend to negative strains (see the file comment).
  enum class Compression { almansi, linear, polynomial };

  /// Default G_s [N/mm]: about 1 % of a compression-knit course stiffness, enough to keep the
  /// tangent regular, too small to matter in the biaxial force.
  static constexpr double kDefaultShearStiffness = 0.01;

  /// General form; coefficients named "C_p_q" then "W_p_q", all 0 unless `c` (same order) is given.
  /// Throws InputError for a monomial with p < 0, q < 0 or p + q = 0 or a repeated monomial in one
  /// force (key `law.response_surface.course` / `.wale`), G_s ≤ 0 or not finite
  /// (`law.response_surface.shear_stiffness`), or a `c` of the wrong size or with non-finite values
  /// (`law.response_surface.coefficients`): the keys of `[law.response_surface]`.
  ResponseSurface(std::vector<Monomial> course, std::vector<Monomial> wale, double G_s = kDefaultShearStiffness,
                  const Eigen::VectorXd& c = {});
  /// The separable form of docs/theory.md §5 with orders (nC, mC, nW, mW) ≥ 0, coefficients a, b, c, d = 0.
  static ResponseSurface separable(int nC, int mC, int nW, int mW, double G_s = kDefaultShearStiffness);
  /// "paper14" = separable(6, 2, 4, 2), "paper24" = separable(6, 6, 6, 6). InputError (key
  /// `law.response_surface.preset`) for another name.
  static ResponseSurface preset(const std::string& name, double G_s = kDefaultShearStiffness);
  static std::vector<std::string> preset_names() { return {"paper14", "paper24"}; }

  std::string name() const override { return "response_surface"; }
  std::vector<std::string> coefficient_names() const override { return names_; }
  Eigen::VectorXd coefficients() const override { return c_; }
  /// InputError (key `law.response_surface.coefficients`) for a wrong size or a non-finite value.
  void set_coefficients(const Eigen::VectorXd& c) override;
  bool linear_in_coefficients() const override { return true; }
  /// det F ≤ 0 gives NaN outputs (the solver reports an invalid state).
  void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const override;
  std::unique_ptr<Law> clone() const override { return std::make_unique<ResponseSurface>(*this); }

  /// (F_C, F_W) [N/mm] at the material-axis Green–Lagrange strains (εC, εW).
  Vec2 forces(double eps_C, double eps_W) const;
  /// T in the material frame (course, wale) [N/mm]; unchanged by a rigid rotation.
  Mat2 material_frame_stress(const LawInput& in) const;
  const std::vector<Monomial>& course_monomials() const { return course_; }
  const std::vector<Monomial>& wale_monomials() const { return wale_; }
  double shear_stiffness() const { return G_s_; }
  Compression compression() const { return compression_; }
  void set_compression(Compression c) { compression_ = c; }

 private:
  ResponseSurface(std::vector<Monomial> course, std::vector<Monomial> wale, double G_s, std::vector<std::string> names);

  std::vector<Monomial> course_, wale_;
  std::vector<std::string> names_;
  Eigen::VectorXd c_;
  double G_s_;
  Compression compression_ = Compression::almansi;
  int max_p_ = 0, max_q_ = 0;  // the highest powers of εC and εW in either list
};

}  // namespace tricot::fem
