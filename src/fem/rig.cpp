// The paper's biaxial-induced rig as an FE fixture (docs/theory.md §6).
#include "tricot/fem/rig.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/core/kinematics.hpp"
#include "tricot/fem/element.hpp"

namespace tricot::fem {

const char* to_string(PullDirection d) { return d == PullDirection::wale ? "wale" : "course"; }

void RigOptions::validate() const {
  // Each option is named by the case file's key: a test's own keys under `test.`, the mesh's under
  // `mesh.` (grading_y is [mesh] grading), the fixture's under `rig.`.
  auto bad = [&](const std::string& key, double got, const std::string& expected) {
    throw InputError(Location{"", 0, key}, "test '" + name + "': out of range", format_number(got), expected);
  };
  if (!(side > 0) || !std::isfinite(side)) bad("test.side", side, "> 0 mm");
  if (!(transverse_strain >= -0.4) || !std::isfinite(transverse_strain))
    bad("test.transverse_strain", transverse_strain, ">= -0.4");
  if (!(pull_strain > 0) || !std::isfinite(pull_strain)) bad("test.pull_strain", pull_strain, "> 0");
  if (steps < 1 || steps > 1000) bad("test.steps", steps, "1 to 1000");
  if (nx < 1 || nx > 2000) bad("mesh.nx", nx, "1 to 2000");
  if (ny < 1 || ny > 2000) bad("mesh.ny", ny, "1 to 2000");
  if (!(grading_x > 0) || !std::isfinite(grading_x)) bad("mesh.grading_x", grading_x, "> 0");
  if (!(grading_y > 0) || !std::isfinite(grading_y)) bad("mesh.grading", grading_y, "> 0");
  if (!(guide_gap >= 0 && guide_gap < 0.5)) bad("rig.guide_gap", guide_gap, "[0, 0.5)");
  if (!(tie_stiffness > 0) || !std::isfinite(tie_stiffness)) bad("rig.tie_stiffness", tie_stiffness, "> 0 N/mm per mm");
  if (!(guide_taper >= 0 && guide_taper + guide_gap < 1)) bad("rig.guide_taper", guide_taper, "[0, 1 - guide_gap)");
  if (!(clip_tie_stiffness > 0) || !std::isfinite(clip_tie_stiffness))
    bad("rig.clip_tie_stiffness", clip_tie_stiffness, "> 0 N/mm per mm");
  if (!(clip_taper >= 0 && clip_taper < 1)) bad("rig.clip_taper", clip_taper, "[0, 1)");
  if (setting_steps < 1 || setting_steps > 1000) bad("rig.setting_steps", setting_steps, "1 to 1000");
}

TestModel make_rig_test(const RigOptions& o) {
  o.validate();
  MeshOptions m;
  m.width = m.height = 0.5 * o.side;
  m.nx = o.nx, m.ny = o.ny, m.type = o.element;
  m.grading = o.grading_y, m.grading_x = o.grading_x;
  TestModel t;
  t.name = o.name;
  t.mesh = make_quarter_mesh(m);
  t.material_angle = o.pull == PullDirection::wale ? 0 : 90;
  t.control = GripControl::displacement;
  t.grip_holds_x = true;  // clips
  t.grip_follows_guide = o.clips_follow_guide;
  t.side = SideEdge::guide;
  t.guide = {m.width * (std::sqrt(1 + 2 * o.transverse_strain) - 1)};
  t.guide_gap = o.guide_gap * m.height;
  t.guide_setting_steps = o.setting_steps;
  t.guide_tie_stiffness = o.tie_stiffness;
  t.guide_taper = o.guide_taper * m.height;
  t.grip_tie_stiffness = o.clip_tie_stiffness;
  t.grip_taper = o.clip_taper * m.width;
  const double d_last = m.height * (std::sqrt(1 + 2 * o.pull_strain) - 1);
  for (int k = 1; k <= o.steps; ++k) t.loads.push_back(d_last * k / o.steps);
  t.validate();
  return t;
}

StrainSpread strain_spread(const TestModel& test, const Eigen::VectorXd& u) {
  const Mesh& m = test.mesh;
  const Mat2 Q = material_axes(test.material_angle);
  auto strains = [&](int e, const Vec2& xi) {
    const Mat2 E = Q.transpose() * green_lagrange(deformation_gradient(m, e, xi, u)) * Q;
    return Vec2(E(0, 0), E(1, 1));
  };
  StrainSpread s;
  s.eC_min = s.eW_min = 1e300, s.eC_max = s.eW_max = -1e300;
  int centre = 0;  // the element at the origin: its corner 0 is the node nearest X = (0, 0)
  double nearest = 1e300;
  for (int e = 0; e < m.elements(); ++e) {
    const Vec2 eps = strains(e, Vec2::Zero());
    s.eC_min = std::min(s.eC_min, eps(0)), s.eC_max = std::max(s.eC_max, eps(0));
    s.eW_min = std::min(s.eW_min, eps(1)), s.eW_max = std::max(s.eW_max, eps(1));
    const double r = m.X.col(m.connectivity[e][0]).norm();
    if (r < nearest) nearest = r, centre = e;
  }
  const Vec2 eps = strains(centre, Vec2(-1, -1));
  s.eC_centre = eps(0), s.eW_centre = eps(1);
  return s;
}

}  // namespace tricot::fem
