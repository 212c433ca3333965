// Global assembly of a test model (docs/theory.md §4, §6, §7), private to fem: which node dofs are unknowns,
// the fixed sparsity pattern of the free-free tangent with a precomputed scatter map, and a colored
// OpenMP loop over elements (elements of one color share no node and no equation, so they write
// without races and the sums do not depend on the thread count).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "tricot/fem/element.hpp"
#include "tricot/fem/law.hpp"
#include "tricot/fem/model.hpp"

namespace tricot::fem::detail {

/// The load parameters of a state: grip displacement d (mm) or full-specimen force F (N), guide c (mm),
/// and the step parameter t of the boundary series (TestModel::conditions: t = k + 1 at step k, 0 at
/// the reference state, between steps linear).
struct Load {
  double d = 0, F = 0, c = 0, t = 0;
};

/// How node dofs map onto the unknowns (docs/theory.md §6). A prescribed dof has eq = −1 and the value
/// d·grip + c·guide; a force-controlled grip makes every top u_y share one equation (`master`),
/// which keeps the edge straight and carries the quarter's share F/2 of the force.
struct DofMap {
  std::vector<int> eq;  ///< per node dof: its equation, or −1 when prescribed
  int equations = 0;
  int master = -1;            ///< the shared grip u_y (force control), else −1
  std::vector<char> grip;     ///< per node dof: u = d (top u_y, displacement control)
  std::vector<double> guide;  ///< per node dof: u = guide·c (1 on the side edge, X/W on a pantograph clamp)
  std::vector<int> top_y;     ///< u_y dofs of the top edge (the grip reaction)
  std::vector<int> right_x;   ///< u_x dofs of the right edge (the guide reaction)
  /// Per node dof: stiffness of a tie (N/mm; a free dof with a spring t·(u − c·guide)), else 0. The
  /// guide's ties anchor at c (guide = 1), the clips' at c·X/W or 0.
  std::vector<double> tie;
  /// Per node dof: the boundary series (index into `series_values`) that prescribes it, or −1.
  std::vector<int> series;
  /// Per node dof: the series whose value its tie pulls toward (a tied condition), or −1.
  std::vector<int> anchor;
  /// Per node dof: the factor of its series' value (1, or the node's coordinate for a proportional
  /// condition, BoundaryCondition::proportional).
  std::vector<double> scale;
  std::vector<std::vector<double>> series_values;  ///< TestModel::conditions' values, one per step
  /// Nodes of each boundary whose resultant is recorded (TestModel::resultant_boundaries()).
  std::vector<std::vector<int>> resultant_nodes;
};
/// The guide wins over a clamped grip at the top-right corner node: the guide sets the width (unless
/// it ends short of the grip, TestModel::guide_gap). A grip that
/// follows the guide (TestModel::grip_follows_guide) prescribes u_x = c·X/W on the top edge.
DofMap make_dof_map(const TestModel& test);

/// Node displacements from the unknowns z and the load.
void expand(const DofMap& dofs, const Eigen::VectorXd& z, const Load& load, Eigen::VectorXd& u);
/// The boundary series' values at step parameter t on their dofs, 0 on every other dof (2·nodes).
Eigen::VectorXd series_displacements(const DofMap& dofs, double t);
/// Where the tie of dof k pulls toward under `load`: c·guide on the quarter, the scaled series value of
/// a tied condition (DofMap::anchor), or 0.
double tie_anchor(const DofMap& dofs, int k, const Load& load);

/// Everything one assembly returns.
struct Assembled {
  Eigen::VectorXd f;                ///< internal force at every node dof (N)
  Eigen::SparseMatrix<double> K;    ///< free-free tangent ∂R_f/∂z, fixed pattern
  Eigen::VectorXd g_grip, g_guide;  ///< ∂R_f/∂d and ∂R_f/∂c at fixed z (K_fp times the load pattern)
  Eigen::VectorXd h_top;            ///< ∂(Σ_top f_y)/∂z, for the force sensitivity
  /// ∂R_f/∂u_s: free equations × node dofs, non-zero in the columns of series dofs (DofMap::series),
  /// for the predictor of an increment of the boundary series.
  Eigen::SparseMatrix<double> K_fs;
  Eigen::MatrixXd df_dc;  ///< ∂f/∂c_k at every node dof (when asked)
  bool symmetric = true;  ///< every element tangent symmetric: Cholesky applies
  ElementStatus status = ElementStatus::ok;
  int element = -1;  ///< the first bad element when status is not ok
  double min_detF = 1;
};

class Assembler {
 public:
  Assembler(const TestModel& test, const DofMap& dofs, const Law& law);
  /// Evaluates every element at u; without `request.tangent`, K, g_*, h_top and `symmetric` keep the
  /// values of the last assembly that had one. Returns false (with a.status/element set) on an inverted element
  /// or a non-finite law value; a's vectors are then meaningless.
  /// The ties (DofMap::tie) pull toward their anchors under `load` (tie_anchor); f then includes the
  /// tie forces.
  bool assemble(const Eigen::VectorXd& u, const LawRequest& request, Assembled& a, const Load& load = {}) const;
  /// The free-free pattern (values zero), for the symbolic factorization.
  const Eigen::SparseMatrix<double>& pattern() const { return pattern_; }

 private:
  const TestModel& test_;
  const DofMap& dofs_;
  const Law& law_;
  Mat2 Q_;
  int coefficient_count_ = 0;
  std::vector<ElementGeometry> geometry_;
  std::vector<std::vector<int>> colors_;  ///< elements per color
  std::vector<int> slot_;                 ///< per element, D×D: index into K.valuePtr(), or −1
  std::vector<int> dof_, eq_;             ///< per element, D: node dof and its equation (−1: prescribed)
  /// Per element: local dofs that are grip / guide dofs, and local dofs on the top edge (u_y).
  std::vector<std::vector<int>> grip_local_, guide_local_, top_local_;
  /// Per element: (local i, local j, index into K_fs.valuePtr()) of a free row and a series column.
  std::vector<std::vector<std::array<int, 3>>> series_entries_;
  Eigen::SparseMatrix<double> pattern_fs_;
  int D_ = 0;  ///< element dofs
  Eigen::SparseMatrix<double> pattern_;
  // Serial or threaded, decided by timing one of each (see assemble()).
  mutable int threaded_ = -1, probes_ = 0;
  mutable double probe_seconds_[2] = {0, 0};
};

}  // namespace tricot::fem::detail
