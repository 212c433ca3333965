// The FE objective (THEORY §2, §7): every test of an experiment simulated with the same law, its
// grip displacement, grip force and field displacements compared with the measured ones at the same
// points and steps, and the exact Jacobian from the FE sensitivities du/dc and dF/dc.
#pragma once

#include <memory>
#include <vector>

#include "tricot/fem/law.hpp"
#include "tricot/fem/locate.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/experiment.hpp"
#include "tricot/ident/groups.hpp"
#include "tricot/ident/problem.hpp"

namespace tricot::ident {

/// Which data enter f and with what weight w_g (THEORY §2); 0 leaves the data out.
struct DataWeights {
  /// ≥ 0. Used for force-controlled tests only: under a displacement-controlled grip the FE
  /// reproduces the measured displacement exactly and the group carries no information.
  double edge_displacement = 1;
  /// ≥ 0. Used for displacement-controlled tests only (the force is the load otherwise).
  double edge_force = 1;
  double field = 1;  ///< ≥ 0, for u and v
  /// true: u and v form one group per test with one scale; false: a group each.
  bool field_uv = false;

  void validate() const;  ///< InputError naming `data.<field>`
};

struct ObjectiveOptions {
  DataWeights weights;
  /// FE settings; `sensitivities` is set by the objective when it needs a Jacobian.
  fem::SolveOptions solver;
  /// Tests simulated in parallel, 0–1024; 0 = OpenMP's default, 1 = one after the other.
  int threads = 0;

  void validate() const;
};

class Objective : public Problem {
 public:
  /// Checks everything before any work (InputError): the experiment; one model per test, same name
  /// and loads (to 1e-9 of the largest); the parameters' names among the law's coefficients (NaN
  /// start = the law's value; their values are trusted: ident::validate() is the caller's check,
  /// repeated here in debug builds only); every field point inside its reference mesh (else one error
  /// saying how many are outside and naming the first: test, id, x, y); at least one data group.
  Objective(std::vector<fem::TestModel> models, Experiment experiment, const fem::Law& law,
            std::vector<Parameter> parameters, ObjectiveOptions options = {});

  const std::vector<Parameter>& parameters() const override { return parameters_; }
  int residuals() const override { return data_.size(); }
  /// Simulates every test with the law's coefficients set to J (in parallel), with sensitivities
  /// when `jacobian`. A test that does not converge, or a point that leaves the deformed mesh
  /// (incremental data), gives ok = false and a message naming the test.
  Evaluation evaluate(const Eigen::VectorXd& J, bool jacobian) const override;
  Eigen::VectorXd residual_variance() const override { return data_.sigma_variance(); }

  const ScaledResiduals& data() const { return data_; }
  const std::vector<fem::TestModel>& models() const { return models_; }
  const Experiment& experiment() const { return experiment_; }
  /// A clone of the law with the identified coefficients set to J (the others as given).
  std::unique_ptr<fem::Law> law_at(const Eigen::VectorXd& J) const;

 private:
  std::vector<fem::TestModel> models_;  // in the experiment's test order
  Experiment experiment_;
  std::unique_ptr<fem::Law> law_;
  std::vector<Parameter> parameters_;
  std::vector<int> coefficient_;  // law coefficient index of each parameter
  ObjectiveOptions options_;
  ScaledResiduals data_;
  std::vector<std::vector<fem::Location>> reference_locations_;  // per test, per point
};

}  // namespace tricot::ident
