// The material law: "the one place you would change" (deal.II step-44). Every law of the
// paper is linear in its coefficients (docs/theory.md §5), so a law can also return ∂P/∂c_k, the basis
// stresses that make exact sensitivities cheap (docs/theory.md §7).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "tricot/core/types.hpp"

namespace tricot::fem {

/// What the out-of-plane direction does (docs/theory.md §5): a membrane or thin sheet is free across its
/// thickness (σ33 = 0, the laws' default); a slice of a thick specimen held across is not (C33 = 1).
enum class Kinematics { plane_stress, plane_strain };
const char* to_string(Kinematics k);  ///< "plane_stress", "plane_strain"

/// The state a law sees at one quadrature point.
struct LawInput {
  Mat2 F = Mat2::Identity();  ///< in-plane deformation gradient ∂x/∂X
  /// Material axes in the reference configuration, as columns: Q.col(0) = course a_C, Q.col(1) =
  /// wale a_W (orthonormal). Identity for isotropic laws and for a test loaded along course = x.
  Mat2 Q = Mat2::Identity();
  /// The region of the point's element (Mesh::region; 0 in a mesh without regions): RegionLaws
  /// evaluates that region's law, every other law ignores it.
  int region = 0;
};

/// What a law returns. Forces are per unit reference length (N/mm): the membrane stress times the
/// reference thickness, because a knit's thickness has no meaning (docs/theory.md §5).
struct LawOutput {
  Mat2 P = Mat2::Zero();    ///< first Piola–Kirchhoff membrane force [N/mm]
  Mat4 A = Mat4::Zero();    ///< consistent tangent ∂P/∂F, A(2i+j, 2k+l) = ∂P_ij/∂F_kl
  double lambda3 = 1.0;     ///< out-of-plane stretch from plane stress (σ33 = 0)
  std::vector<Mat2> dP_dc;  ///< ∂P/∂c_k for every coefficient k (only when asked)
};

/// What to compute besides P.
struct LawRequest {
  bool tangent = true;
  bool sensitivities = false;
};

/// A constitutive law in plane stress. Implementations are immutable once built except through
/// set_coefficients(); evaluate() is const and thread-safe.
///
/// A constructor or set_coefficients() throws InputError for a bad coefficient, naming it by its key
/// in the config's law table: `law.<table>.<key>` (`law.neo_hookean.mu`, `law.mooney_rivlin.values`),
/// `law.<table>` for the list as a whole. That is the key itself for [law]. A law cannot know whether
/// it was read from [law] or from a [[law.region]] (`law.region[N]`, with the same sub-tables), so
/// `law.` stands for its law table, which places the key (project::LawSpec).
class Law {
 public:
  virtual ~Law() = default;
  virtual std::string name() const = 0;
  /// Names of the identifiable coefficients, in the order of coefficients().
  virtual std::vector<std::string> coefficient_names() const = 0;
  virtual Eigen::VectorXd coefficients() const = 0;
  virtual void set_coefficients(const Eigen::VectorXd& c) = 0;
  /// P(F; c) = P0(F) + Σ_k c_k B_k(F) (docs/theory.md §5). When true, dP_dc = B_k exactly.
  virtual bool linear_in_coefficients() const = 0;
  virtual void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const = 0;
  virtual std::unique_ptr<Law> clone() const = 0;

  /// Cauchy membrane force per unit current length, σ·t = P Fᵀ / det F (in plane).
  static Mat2 cauchy(const Mat2& F, const Mat2& P) { return P * F.transpose() / F.determinant(); }
};

/// Strong ellipticity of a tangent A = ∂P/∂F at one state: the acoustic tensor Q(N)_ik = A_iJkL N_J N_L
/// for a unit direction N of the reference configuration, and the smallest eigenvalue of its
/// symmetric part over all N. Positive: every incremental wave propagates, the state is stable against
/// localisation; ≤ 0: the material can form a band of arbitrarily steep gradient normal to N (the FE
/// then localises into single elements, which invert or shear flat).
struct Ellipticity {
  double min_eigenvalue = 0;  ///< min over N of λ_min(sym Q(N)) [N/mm]
  double angle_deg = 0;       ///< N = (cos, sin) of this angle from x, in [0, 180)
};
/// Samples N every 5° and refines each local minimum by golden section (to ~1e-6°).
Ellipticity strong_ellipticity(const Mat4& A);
/// The acoustic tensor Q_ik(N) = A_ijkl N_j N_l of a tangent A (rows 2i + j, columns 2k + l).
Mat2 acoustic_tensor(const Mat4& A, const Vec2& N);

}  // namespace tricot::fem
