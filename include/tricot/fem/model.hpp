// Finite-element models of tests (docs/theory.md §6): either the paper's quarter specimen (paper §3.2.2,
// Fig. 5) with symmetry on x = 0 and y = 0, a grip on the top edge and a free or guided side edge; or
// any mesh with conditions per named boundary and per component (fixed, or a prescribed series of
// values, one per step), whose measured force is the resultant of a named boundary.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tricot/fem/mesh.hpp"

namespace tricot::fem {

/// What the side edge x = W does.
enum class SideEdge {
  free,   ///< traction free (uniaxial test)
  guide,  ///< u_x = c (the transverse dimension held: biaxial-induced test), u_y free
};

/// What the top edge y = H does.
enum class GripControl {
  displacement,  ///< u_y = d(t) on every top node
  force,         ///< the top edge stays straight (one shared u_y) and carries the full-specimen force F(t)
};

/// One displacement condition on one component of a named boundary (docs/theory.md §6). Symmetry about a line
/// x = const or y = const is a fixed normal component; a rigid grip is both components prescribed
/// (every node of the boundary moves alike) with its resultant measured (TestModel::force_boundary);
/// a compliant grip or a guide holds a component through ties instead (`tie`).
struct BoundaryCondition {
  BoundaryCondition() = default;
  /// Fixed (no values) or prescribed per step, rigid.
  BoundaryCondition(std::string name, int c, std::vector<double> v = {})
      : boundary(std::move(name)), component(c), values(std::move(v)) {}

  std::string boundary;  ///< a name in Mesh::boundaries
  int component = 0;     ///< 0 = u_x, 1 = u_y
  /// The displacement at each load step (mm; any sign, not necessarily monotone: loading, holds,
  /// unloading), one value per step; between steps it varies linearly from 0 at the reference state.
  /// Empty = fixed (u = 0).
  std::vector<double> values;
  /// The values are displacements per mm of the node's coordinate along `component` (u = value · X or
  /// value · Y): a clamp that spreads about the axis, as the rig's pantograph clips do (docs/theory.md §6).
  bool proportional = false;
  /// > 0: the component is held by compliant ties (N/mm per mm of boundary) that pull it toward the
  /// prescribed value instead of prescribing it: a spring on each node of stiffness `tie` × its share
  /// of the boundary's length (tie_consistent) × the taper. The dof stays free.
  double tie = 0;
  /// With a tie: where it ends. The tie then runs along the boundary (an open chain of element sides)
  /// from the end farther from this point up to the boundary's point closest to it; the nodes the tie
  /// does not reach are left as they were. Empty = the whole boundary.
  std::optional<Vec2> tie_end;
  /// With tie_end: over this length (mm, ≥ 0) before the end the stiffness falls linearly to zero, as
  /// the fabric leaves a guide's rounded end.
  double tie_taper = 0;
  /// How the tie is lumped on the nodes. true: consistently, ∫ tie · taper · N_i ds over each element
  /// side's tied part, so that a uniform tie loads a quadratic side as a uniform traction does (a
  /// uniformly pulled sheet stays homogeneous). false: the built-in rig's rule, half of each
  /// node-to-node segment (mid-side nodes included) to each node before the end, the taper at the node;
  /// the same on linear sides, not on quadratic ones.
  bool tie_consistent = true;
};

/// One physical test, loaded through a list of steps.
struct TestModel {
  std::string name = "test";
  Mesh mesh;
  /// Angle in degrees from the x axis (the loading direction is y) to the course direction a_C. The
  /// wale a_W is a_C turned +90°. 0 = course along x, so a test loaded along y pulls the wale.
  double material_angle = 0;
  GripControl control = GripControl::displacement;
  /// Grip: also hold u_x = 0 on the top edge (a clamp); false = sliding grip (homogeneous states).
  bool grip_holds_x = true;
  /// Pantograph clamp (needs grip_holds_x and a guide): the clamp's width opens with the guide, u_x =
  /// c(t)·X/W on the top edge instead of 0, so a clamped grip and a moving guide agree at the corner.
  bool grip_follows_guide = false;
  SideEdge side = SideEdge::free;
  /// Step loads, strictly increasing from > 0: the grip displacement d(t) in mm (quarter model, so
  /// the full specimen stretches by 2d) or the full-specimen force in N.
  std::vector<double> loads;
  /// Guide: u_x = c on the side edge, mm (negative = the specimen is narrowed). One value for all
  /// steps, or one per step (the guide is moved proportionally otherwise: c · load/load_last).
  std::vector<double> guide;
  /// The paper's rig (docs/theory.md §6): the guide ends this far (mm, ≥ 0, < the specimen's half height)
  /// short of the grip: right-edge nodes with Y > H − guide_gap are free, so the clip–guide corner is
  /// not a singular point. 0 = the guide covers the whole side edge.
  double guide_gap = 0;
  /// > 0 (needs a guide with one value): the transverse dimension is set first, in this many
  /// increments with the grip at rest (clips follow the guide when grip_follows_guide), then held at
  /// `guide` for every load step, as the paper does ("uniaxial tests are repeated for various fixed
  /// transverse dimensions"). 0 = the guide moves with the load (see `guide`). 0–1000.
  int guide_setting_steps = 0;
  /// > 0: the fabric is tied to the guide by compliant ties (N/mm per mm of edge, lumped on the
  /// side-edge nodes) instead of having u_x prescribed: a spring t·(u_x − c) per node. Together with
  /// guide_taper this removes the singular point where the guide ends. 0 = a rigid guide.
  double guide_tie_stiffness = 0;
  /// Over the last guide_taper mm of the guide (≥ 0; needs ties) the tie stiffness falls linearly to
  /// zero, as the fabric leaves the guide's rounded end.
  double guide_taper = 0;
  /// > 0 (needs grip_holds_x): the clips hold u_x through compliant ties (N/mm per mm of grip) toward
  /// their prescribed position (0, or c·X/W when grip_follows_guide) instead of prescribing it; u_y
  /// stays prescribed. 0 = rigid clips.
  double grip_tie_stiffness = 0;
  /// Over the last grip_taper mm of the grip before the side edge (≥ 0, < the half width; needs grip
  /// ties) the clip ties fall linearly to zero: the corner where the clips meet the free stretch of the
  /// side is then a roller, not a singular clamp–free corner.
  double grip_taper = 0;

  /// Conditions per named boundary (docs/theory.md §6). Non-empty = a model of any mesh: the quarter's own
  /// conditions above (control, side, guide, grip ties) are then unused and must keep their defaults,
  /// `loads` are step labels (strictly increasing, e.g. frame numbers or times), and every boundary
  /// that no condition names is free. A later condition on the same node and component wins.
  std::vector<BoundaryCondition> conditions;
  /// With conditions: the boundary whose resultant is the test's measured force
  /// (StepResult::edge_force = force_scale × Σ of its nodes' internal forces along force_component;
  /// StepResult::edge_displacement = the prescribed value of that component there). Empty = no force.
  std::string force_boundary;
  int force_component = 1;  ///< 0 = x, 1 = y
  double force_scale = 1;   ///< > 0: 2 for a half model whose symmetry carries the other half
  /// Every step's resultant (both components, internal force summed over the nodes) is recorded for
  /// these boundaries (StepResult::resultants, in this order); empty = those that a condition names.
  std::vector<std::string> resultants;

  bool has_conditions() const { return !conditions.empty(); }
  /// The tie stiffness (N/mm) of each node that condition `i` ties (BoundaryCondition::tie, tie_end,
  /// tie_taper, tie_consistent), by node. InputError naming `test.conditions[i].tie_end`
  /// when the end is given and the boundary is not one open line, `…tie` when it has no length.
  std::vector<std::pair<int, double>> tie_stiffness(size_t i) const;
  /// The boundaries whose resultants are recorded (see `resultants`).
  std::vector<std::string> resultant_boundaries() const;

  /// Throws InputError naming `test.<field>` (with the test's name) when inconsistent.
  void validate() const;

 private:
  void validate_conditions() const;
};

}  // namespace tricot::fem
