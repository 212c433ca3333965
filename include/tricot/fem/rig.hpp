// The paper's biaxial-induced rig as an FE fixture (docs/theory.md §6; paper §3.1.2, Figs 3–5): a quarter of a
// square specimen, clipped at the grip, tied to lateral guides that hold the transverse dimension but
// let the fabric slide along the pull, the guides ending short of the clips. The transverse dimension
// is set first with the grip at rest, then held while the grip pulls.
#pragma once

#include <Eigen/Core>
#include <string>

#include "tricot/core/options.hpp"
#include "tricot/fem/model.hpp"

namespace tricot::fem {

/// Which material direction the grip pulls (the load cell measures the force along it only).
enum class PullDirection {
  wale,    ///< wale along the pull (y), course across: material_angle 0
  course,  ///< course along the pull (y), wale across: material_angle 90
};
const char* to_string(PullDirection d);  ///< "wale", "course"

struct RigOptions {
  std::string name = "rig";
  /// Full specimen side, mm, > 0 (the paper: 110 or 150); the model is the quarter side/2 × side/2.
  double side = 110;
  PullDirection pull = PullDirection::wale;
  /// Green–Lagrange strain the guides impose across the pull, ≥ −0.4 (0 = the width held at its
  /// initial value; the knit's shrinkage then loads it): guide u_x = W(√(1 + 2ε) − 1).
  double transverse_strain = 0;
  /// Nominal Green–Lagrange strain along the pull at the last step, > 0: grip
  /// d_last = H(√(1 + 2ε) − 1), reached in `steps` equal increments.
  double pull_strain = 0.5;
  int steps = 21;  ///< load steps, 1–1000
  /// Elements along x and y of the quarter, 1–2000 each (the paper: 120 Q8, e.g. 12 × 10).
  int nx = 12, ny = 10;
  ElementType element = ElementType::Q8;
  /// First-over-last element size along y (< 1 refines toward the grip) and along x (< 1 refines
  /// toward the guide), > 0.
  double grading_y = 0.5, grading_x = 0.5;
  /// How far the guide ends short of the grip, as a fraction of the quarter's height, [0, 0.5).
  double guide_gap = 0.15;
  /// Ties to the guide, N/mm per mm of edge (> 0), and the length of the guide's tapered end as a
  /// fraction of the quarter's height, [0, 0.5): compliant, tapered ties leave no singular point.
  double tie_stiffness = 2.0;
  double guide_taper = 0.15;
  /// Clip ties along x, N/mm per mm of grip (> 0), and their taper toward the side edge as a fraction
  /// of the quarter's width, [0, 1): the clip–free-side corner becomes a roller.
  double clip_tie_stiffness = 2.0;
  double clip_taper = 0.15;
  /// Increments that set the transverse dimension before the pull, 1–1000.
  int setting_steps = 4;
  /// Clips spread with the guide setting (u_x = c·X/W on the grip, the guide bars being mounted on
  /// the clips) when true; false = the clips keep the initial width (u_x = 0).
  bool clips_follow_guide = true;

  /// The config keys of [rig] (core/options.hpp); the other options are the test's, from its [[test]]
  /// and [mesh]. No key declares a range: validate()'s bounds are open or span keys, and its messages
  /// name the test.
  static auto keys() {
    using O = RigOptions;
    return std::tuple{
        option(&O::guide_gap, "rig.guide_gap",
               "The guide ends this fraction of the quarter's height short of the clips, [0, 0.5)."),
        option(&O::guide_taper, "rig.guide_taper",
               "The guide's ties fade to zero over this fraction of the quarter's height, [0, 1 - guide_gap)."),
        option(&O::tie_stiffness, "rig.tie_stiffness", "Fabric-to-guide ties, N/mm per mm of edge, > 0."),
        option(&O::clip_tie_stiffness, "rig.clip_tie_stiffness", "Clip ties holding u_x, N/mm per mm of grip, > 0."),
        option(&O::clip_taper, "rig.clip_taper",
               "The clip ties fade to zero toward the side over this fraction of the quarter's width, [0, 1)."),
        option(&O::clips_follow_guide, "rig.clips_follow_guide",
               "The clips spread with the guide setting (guides mounted on the clips); false = clips keep the "
               "width."),
        option(&O::setting_steps, "rig.setting_steps",
               "Increments that set the transverse dimension before the pull, 1–1000.")};
  }
  /// InputError naming the case file's key: `test.side`, `test.transverse_strain`, `test.pull_strain`,
  /// `test.steps`; `mesh.nx`, `mesh.ny`, `mesh.grading` (grading_y), `mesh.grading_x`; `rig.<field>`.
  void validate() const;
};

/// The TestModel of one biaxial-induced test (validated).
TestModel make_rig_test(const RigOptions& options);

/// Range of the material-frame Green–Lagrange strains over the field: εC and εW at every element
/// centre of `test`'s mesh under displacements `u` (a StepResult's), and at the specimen centre.
struct StrainSpread {
  double eC_min = 0, eC_max = 0, eW_min = 0, eW_max = 0;
  double eC_centre = 0, eW_centre = 0;  ///< at X = (0, 0)
  double eC_spread() const { return eC_max - eC_min; }
  double eW_spread() const { return eW_max - eW_min; }
};
StrainSpread strain_spread(const TestModel& test, const Eigen::VectorXd& u);

}  // namespace tricot::fem
