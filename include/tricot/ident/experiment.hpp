// What was measured (docs/theory.md §1–§2, §7): per physical test, the load steps, the grip's displacement
// and force, and displacements at points of the specimen, with optional measurement σ. The CLI fills
// it from files; the identification compares it with the FE at the same points and steps.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace tricot::ident {

/// How the field displacements were measured (docs/theory.md §7, paper §3.1.3).
enum class FieldKind {
  /// u(X, t_k): total displacement of material points tracked from the reference image. The FE
  /// value is interpolated at X in the reference mesh.
  cumulative,
  /// x(t_k) − x(t_{k−1}): displacement between consecutive images of the material under a point
  /// fixed in the images (the paper's window centres). The FE value is interpolated where the point
  /// sits in the deformed mesh of step k − 1 (the reference mesh for the first step).
  incremental,
};
const char* to_string(FieldKind k);  ///< "cumulative", "incremental"

/// Measurement standard deviations, in the data's units; 0 = unknown, and the group is then scaled
/// by the RMS of its data (docs/theory.md §2). Given σ make f a χ²/2 and the covariance a real one (§8).
struct Sigma {
  double edge_displacement = 0;  ///< mm, ≥ 0
  double edge_force = 0;         ///< N, ≥ 0
  double field = 0;              ///< mm, ≥ 0, for u and v alike
};

/// The data of one physical test. Step k (0-based) is the state under loads[k]; the unloaded
/// reference state is not a step.
struct TestData {
  std::string name;    ///< the fem::TestModel it belongs to (same name), unique in the experiment
  std::string source;  ///< where the data came from (a file), only for error messages; may be empty
  /// Step loads, as fem::TestModel::loads: grip displacement (mm) or full-specimen force (N).
  std::vector<double> loads;
  /// Grip displacement per step (mm) as fem::StepResult::edge_displacement: u_y of the quarter
  /// model's grip, i.e. half the cross-head travel. Empty = not measured.
  std::vector<double> edge_displacement;
  /// Full-specimen grip force per step (N), as fem::StepResult::edge_force. Empty = not measured.
  std::vector<double> edge_force;

  FieldKind field_kind = FieldKind::cumulative;
  /// Field points: an id each (kept for messages and outputs) and the position in mm in model
  /// coordinates (quarter specimen, x ≥ 0 from the axis of symmetry, y ≥ 0 from the other).
  /// cumulative: the reference position X; incremental: the fixed position in the images.
  std::vector<int> point_ids;
  Eigen::Matrix2Xd points;
  /// Measured displacements (mm), steps × points; both empty = no field data.
  Eigen::MatrixXd u, v;

  Sigma sigma;
  /// Per-point σ of u and v (mm), steps × points, as the DIC gives them (tricot experiment's field.csv);
  /// both empty = σ.field for every value. When given they replace σ.field (docs/theory.md §8).
  Eigen::MatrixXd sigma_u, sigma_v;
  /// Weight of each step's data (≥ 0, finite; one per step), multiplying w_g of every group of the
  /// test at that step; empty = 1 for every step. A domain-weighted identification (paper §4.3.2,
  /// docs/theory.md §9 [choice]: `[data] domain_weight`) sets it below 1 for the steps outside the domain.
  std::vector<double> step_weight;

  int steps() const { return static_cast<int>(loads.size()); }
  /// The data of the steps `keep` (0-based, increasing, in range) alone, in their order: the steps to
  /// fit chosen among the frames. Cumulative field data only (an incremental one refers to the step
  /// before).
  TestData select_steps(const std::vector<int>& keep) const;
  int point_count() const { return static_cast<int>(points.cols()); }
  bool has_field() const { return points.cols() > 0; }

  /// Throws InputError (key `experiment.<name>.<field>`, file = source) for: no steps, loads not
  /// finite or not strictly increasing, a per-step list or matrix of the wrong size, a non-finite
  /// value (naming the step and point), duplicate point ids, a negative or non-finite σ.
  void validate() const;
};

struct Experiment {
  std::vector<TestData> tests;

  /// Validates every test and that names are unique and non-empty (InputError).
  void validate() const;
  /// The test named `name`, or nullptr.
  const TestData* find(const std::string& name) const;
};

}  // namespace tricot::ident
