// A least-squares problem in the identified coefficients J: the scaled residuals r(J) of eq. (1)
// and their Jacobian, exact or by finite differences (docs/theory.md §2, §3, §7). The FE objective
// (objective.hpp) is one; tests use analytic ones.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

namespace tricot::ident {

/// One identified coefficient (docs/theory.md §3).
struct Parameter {
  std::string name;  ///< the law's coefficient name, e.g. "C10"
  /// Start value; NaN = the law's current value (resolved by the objective).
  double start = std::numeric_limits<double>::quiet_NaN();
  /// > 0: LM works in x = J / scale. 0 = |start|, which makes LM's steps relative, as the paper's
  /// J_{i+1} = J_i + t_i∘J_i. A zero start needs an explicit scale.
  double scale = 0;
  double lower = -std::numeric_limits<double>::infinity();  ///< bound on J, < upper
  double upper = std::numeric_limits<double>::infinity();   ///< bound on J

  /// The scale LM uses: `scale`, or |start| when scale is 0.
  double resolved_scale() const;
};
/// The suffix of a test's force scale k, a parameter named `<test>.force_scale`: that test's grip force
/// is k times the law's (ident::Objective; docs/theory.md §2).
inline constexpr const char* kForceScale = "force_scale";
/// The test whose force scale `parameter` names ("X2" for "X2.force_scale"); empty when it names none.
std::string force_scale_test(const std::string& parameter);

/// Throws InputError naming `parameters.<name>.<field>` for: an empty or repeated name, a
/// non-finite start, lower ≥ upper, a start outside the bounds, a negative or non-finite scale, or
/// a zero start without a scale. identify() calls it; Objective trusts its parameters (checked by
/// its caller: project::IdentificationSpec::validate() makes these checks at the config's keys) and
/// calls it in debug builds only.
void validate(const std::vector<Parameter>& parameters);

/// r(J) and, when asked, ∂r/∂J.
struct Evaluation {
  /// false: the model could not be evaluated at J (the FE did not converge, a point left the
  /// deformed mesh, …). r and jacobian are then meaningless; `message` says why.
  bool ok = false;
  std::string message;
  Eigen::VectorXd y;         ///< model values, stacked like r (unscaled, in the data's units)
  Eigen::VectorXd r;         ///< scaled residuals, eq. (1)
  Eigen::MatrixXd jacobian;  ///< ∂r/∂J, residuals × parameters, physical J; empty when not asked
  int evaluations = 0;       ///< r(J) computations it took (1, plus one per finite-difference trial)

  double objective() const { return 0.5 * r.squaredNorm(); }  ///< f of eq. (1)
};

class Problem {
 public:
  virtual ~Problem() = default;
  /// The identified coefficients, start values resolved (finite).
  virtual const std::vector<Parameter>& parameters() const = 0;
  virtual int residuals() const = 0;
  /// r(J) and, when `jacobian` is true, the exact ∂r/∂J. Thread-safe: called concurrently for the
  /// columns of a finite-difference Jacobian and for the stability test.
  virtual Evaluation evaluate(const Eigen::VectorXd& J, bool jacobian) const = 0;
  /// Whether evaluate() can give an exact Jacobian; if not, only finite differences are allowed.
  virtual bool has_exact_jacobian() const { return true; }
  /// docs/theory.md §8: Var(r_i) when every scale is a measurement σ (ScaledResiduals::sigma_variance());
  /// empty = estimate σ̂² = 2f/(N − n) from the fit.
  virtual Eigen::VectorXd residual_variance() const { return {}; }
  /// A lower bound of f(J) that needs no FE run (the stability barrier's part of f), 0 by default:
  /// a trial point it puts above the f to beat cannot beat it, and is rejected without the FE. LM
  /// also keeps its steps from growing it much (IdentifyOptions::barrier_growth).
  virtual double lower_bound(const Eigen::VectorXd& J) const {
    (void)J;
    return 0;
  }
  /// Whether lower_bound() can be other than 0.
  virtual bool has_lower_bound() const { return false; }
  /// Whether a Jacobian asked for at one of the last points evaluated without it costs less than an
  /// evaluation with it (ObjectiveOptions::sensitivities_after). LM then asks for it only where it
  /// needs it, and its bounded line search interpolates f alone.
  virtual bool keeps_simulations() const { return false; }
};

enum class JacobianMode {
  exact,              ///< from the problem (FE sensitivities, docs/theory.md §7)
  finite_difference,  ///< the paper's way: one perturbed evaluation per column (two when central)
};
enum class Difference { forward, central };
const char* to_string(JacobianMode m);  ///< "exact", "finite_difference"
const char* to_string(Difference d);    ///< "forward", "central"

/// How evaluate() computes ∂r/∂J: IdentifyOptions's jacobian, difference, fd_step and threads, which
/// it declares and checks (IdentifyOptions::jacobian_options()).
struct JacobianOptions {
  JacobianMode mode = JacobianMode::exact;
  Difference difference = Difference::forward;
  /// Finite-difference step in LM units, (0, 0.1]: h_k = step · scale_k (a relative step).
  double step = 1e-6;
  /// Threads for the finite-difference columns, 0–1024; 0 = OpenMP's default.
  int threads = 0;
};

/// r(J) and, when `jacobian`, ∂r/∂J by `options.mode`. Finite differences evaluate the columns in
/// parallel; a forward trial that fails is retried backward, a central one falls back to one side.
/// `base`, when given, is r(J) already computed (saves one evaluation for forward differences).
Evaluation evaluate(const Problem& problem, const Eigen::VectorXd& J, bool jacobian, const JacobianOptions& options,
                    const Evaluation* base = nullptr);

/// The OpenMP team for `threads` asked (0: OpenMP's default): at most the cores, since more never
/// speeds an evaluation up and a team of 1024 can fail to start (libgomp aborts).
int thread_team(int threads);

}  // namespace tricot::ident
