// The FE objective (docs/theory.md §2, §7): every test of an experiment simulated with the same law, its
// grip displacement, grip force and field displacements compared with the measured ones at the same
// points and steps, and the exact Jacobian from the FE sensitivities du/dc and dF/dc.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "tricot/core/options.hpp"
#include "tricot/fem/law.hpp"
#include "tricot/fem/locate.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/experiment.hpp"
#include "tricot/ident/groups.hpp"
#include "tricot/ident/problem.hpp"

namespace tricot::ident {

/// Which data enter f and with what weight w_g (docs/theory.md §2); 0 leaves the data out.
struct DataWeights {
  /// ≥ 0. Used for force-controlled tests only: under a displacement-controlled grip the FE
  /// reproduces the measured displacement exactly and the group carries no information.
  double edge_displacement = 1;
  /// ≥ 0. Used for displacement-controlled tests only (the force is the load otherwise).
  double edge_force = 1;
  double field = 1;  ///< ≥ 0, for u and v
  /// true: u and v form one group per test with one scale; false: a group each.
  bool field_uv = false;
  /// true: the weights are absolute, per value (ScaledResiduals(true)): f = ½ Σ_g w_g Σ_i (y_i − y*_i)²;
  /// false: eq. (1), each group divided by its size and its σ or RMS (docs/theory.md §2).
  bool fixed = false;

  void validate() const;  ///< InputError naming `data.<field>`
};

struct ObjectiveOptions {
  DataWeights weights;
  /// FE settings; `sensitivities` is set by the objective when it needs a Jacobian.
  fem::SolveOptions solver;
  /// Tests simulated in parallel, 0–1024; 0 = OpenMP's default, 1 = one after the other.
  int threads = 0;
  /// true: the tests are simulated without sensitivities, which are added afterwards from their
  /// converged states (fem::add_sensitivities) when the Jacobian is asked for, and the last
  /// simulations are kept: the Jacobian at a point evaluated before costs its sensitivities alone.
  /// It pays where most evaluations are trials whose Jacobian is never used (LM with bounds: its line
  /// search; `project-110.toml` took 19.5 s CPU instead of 29.1 s) and costs where each
  /// trial's is (a factorization per step more: the Table 1 identification 2.6 s against 2.0 s).
  /// Used only when every test has fewer than fem::kSensitivitiesAfterBelow unknowns: above, it
  /// costs a factorization per step more than the sensitivities with the solve. The project sets it
  /// when a coefficient has bounds.
  bool sensitivities_after = false;
  /// true: every evaluation's FE starts from the simulations of the last evaluation with a Jacobian
  /// (fem::SolveOptions::warm_start): Newton starts at those states moved by their du/dc · Δc, and
  /// the rig's setting takes one increment. Where the law moved little since, most steps take one
  /// factorization (a 12 × 10 rig test, coefficients ±1 %: 22 against 57; docs/validation.md "The
  /// paper's scale by mesh levels"); where it moved far they take the load path. The values then
  /// agree with a cold evaluation's to the FE tolerance, not bit for bit, and depend on the
  /// evaluations before.
  bool warm_start = false;

  /// The config key of [identify] these options hold (core/options.hpp); the others come from [data],
  /// [solver] and IdentifyOptions's threads.
  static auto keys() {
    using O = ObjectiveOptions;
    return std::tuple{
        option(&O::warm_start, "identify.warm_start",
               "Start each step's Newton from the step before, moved by the last evaluation with a Jacobian's\n"
               "increment (its states moved by their sensitivities), instead of along the load path: on large\n"
               "meshes an evaluation near the last costs about 40 % less (the paper-scale fixture, 24 874 dofs:\n"
               "7.5 s against 12.3 s). The values then\n"
               "agree with a cold evaluation's to the FE tolerance, not bit for bit. See docs/validation.md.")};
  }
  void validate() const;
};

/// One test's share of an evaluation: the rows of y of its data groups (in the data's order) and
/// their ∂y/∂J, or why it failed.
struct TestValues {
  bool ok = false;
  std::string message;  ///< !ok: why, naming the test; empty for a test that was not run (cancelled)
  Eigen::VectorXd y;    ///< the test's rows of y, unscaled, its groups one after the other
  Eigen::MatrixXd dy_dJ;  ///< ∂y/∂J of those rows (physical J); empty without a Jacobian
};

/// Spreads an Objective's tests over processes (the MPI ranks of `mpirun -np N tricot identify`,
/// src/mpi). ident only sees this interface: it never includes MPI.
class TestSplit {
 public:
  virtual ~TestSplit() = default;
  /// The values of all `tests` tests at J (index = test): this process's share from `local` (called
  /// with its test indices, ascending), the others' from the other processes. Thread-safe.
  virtual std::vector<TestValues> evaluate(
      const Eigen::VectorXd& J, bool jacobian, int tests,
      const std::function<std::vector<TestValues>(const std::vector<int>&)>& local) const = 0;
};

class Objective : public Problem {
 public:
  /// Checks everything before any work (InputError): the experiment; one model per test, same name
  /// and loads (to 1e-9 of the largest); the parameters' names among the law's coefficients (NaN
  /// start = the law's value), followed by any force scales `<test>.force_scale` (NaN start = 1): a
  /// scaled test's grip force is k times the law's, for displacement-controlled tests only, and one
  /// test with force data at least keeps its own (a scale of a test this experiment lacks has no
  /// effect: a one-test objective takes the whole parameter vector). Their values are trusted: ident::validate() is the
  /// caller's check, repeated here in debug builds only); every field point inside its reference mesh (else one error
  /// saying how many are outside and naming the first: test, id, x, y); at least one data group.
  Objective(std::vector<fem::TestModel> models, Experiment experiment, const fem::Law& law,
            std::vector<Parameter> parameters, ObjectiveOptions options = {});

  const std::vector<Parameter>& parameters() const override { return parameters_; }
  int residuals() const override { return data_.size(); }
  /// Simulates every test with the law's coefficients set to J (in parallel), with sensitivities
  /// when `jacobian` (ObjectiveOptions::sensitivities_after: added afterwards, from the simulations
  /// of the last points when J is one of them). A Jacobian evaluation at the point of the last one
  /// is that one again. A test that does not converge, or a point that
  /// leaves the deformed mesh (incremental data), gives ok = false and a message naming the test.
  /// With a TestSplit, the tests are spread over its processes; the answer is the same bit for bit.
  Evaluation evaluate(const Eigen::VectorXd& J, bool jacobian) const override;
  /// The values of `tests` (indices into models()) at J, simulated in parallel threads, in order();
  /// the other entries stay empty. A failed test leaves the tests after it in order() unrun (empty
  /// message) or stopped at their next increment; the first failing one in order() always runs to its
  /// end and says why, so the failed test and its message do not depend on threads or processes.
  std::vector<TestValues> evaluate_tests(const Eigen::VectorXd& J, bool jacobian, const std::vector<int>& tests) const;
  /// evaluate()'s tests go through `split` from now on (nullptr: all in this process).
  void set_split(std::shared_ptr<const TestSplit> split) { split_ = std::move(split); }
  Eigen::VectorXd residual_variance() const override { return data_.sigma_variance(); }

  const ScaledResiduals& data() const { return data_; }
  const std::vector<fem::TestModel>& models() const { return models_; }
  /// The tests' evaluation order (indices into models()): the most stretched first (nominal strains
  /// of the last step, along the pull and across it). They cost the most, so the threads finish
  /// together, and they are where a trial law fails, so a failed evaluation stops early. A failed
  /// evaluation reports the first failed test in this order.
  const std::vector<int>& order() const { return order_; }
  bool keeps_simulations() const override { return after_; }
  const Experiment& experiment() const { return experiment_; }
  /// A clone of the law with the identified coefficients set to J (the others as given).
  std::unique_ptr<fem::Law> law_at(const Eigen::VectorXd& J) const;
  /// How many of parameters() are the law's coefficients: the first ones; the force scales follow.
  int law_parameters() const { return static_cast<int>(coefficient_.size()); }
  /// Test `test`'s force scale k at J (its model force is k times the law's; 1 when it has none).
  double force_scale(const Eigen::VectorXd& J, int test) const;
  /// Every test simulated with the law at J (e.g. the answer's fits): the last evaluation's
  /// simulations where they are at J (warm_start, sensitivities_after), else fresh runs in parallel
  /// threads; an unusable run says why in its message.
  std::vector<fem::SimulationResult> simulations(const Eigen::VectorXd& J) const;

 private:
  std::vector<fem::TestModel> models_;  // in the experiment's test order
  Experiment experiment_;
  std::unique_ptr<fem::Law> law_;
  std::vector<Parameter> parameters_;
  std::vector<int> coefficient_;    // law coefficient index of each of the first parameters
  std::vector<int> scale_of_test_;  // per test: the index of its force scale in parameters_, or −1
  ObjectiveOptions options_;
  ScaledResiduals data_;
  std::vector<std::vector<fem::Location>> reference_locations_;  // per test, per point
  std::shared_ptr<const TestSplit> split_;
  bool after_ = false;      // ObjectiveOptions::sensitivities_after, where every test is small enough
  std::vector<int> order_;  // order()
  std::vector<int> rank_;   // rank_[t]: t's place in order_
  Evaluation evaluate_afresh(const Eigen::VectorXd& J, bool jacobian) const;  // evaluate() without the memo
  /// The simulations (without sensitivities) of the last points evaluated, newest first, per test
  /// (an unusable or unrun test's is not kept).
  struct Simulated {
    Eigen::VectorXd J;
    std::vector<std::optional<fem::SimulationResult>> tests;
  };
  static constexpr std::size_t kSimulated = 4;
  mutable std::deque<Simulated> simulated_;
  /// ObjectiveOptions::warm_start: the law's coefficients and the simulations (with sensitivities) of
  /// the last evaluation with a Jacobian where every test ran.
  struct Warm {
    Eigen::VectorXd c;
    std::vector<std::optional<fem::SimulationResult>> tests;
  };
  mutable std::shared_ptr<const Warm> warm_;
  /// The last evaluation with a Jacobian that succeeded (computed in this process): evaluate() at
  /// the same point returns it (e.g. the identifiability report at LM's answer).
  mutable std::optional<Evaluation> last_jacobian_;
  mutable Eigen::VectorXd last_jacobian_at_;
  mutable std::mutex simulated_mutex_;  // guards simulated_, warm_ and last_jacobian_
};

}  // namespace tricot::ident
