// FE values at the measured steps and points (docs/theory.md §7).
#include "predict.hpp"

#include <Eigen/LU>
#include <cstdio>
#include <optional>

#include "tricot/core/error.hpp"
#include "tricot/fem/element.hpp"

namespace tricot::ident::detail {

Eigen::VectorXd stack(const Eigen::MatrixXd& F) {
  Eigen::VectorXd y(F.size());
  for (Eigen::Index k = 0, i = 0; k < F.rows(); ++k)
    for (Eigen::Index p = 0; p < F.cols(); ++p) y(i++) = F(k, p);
  return y;
}

Eigen::VectorXd stack_uv(const Eigen::MatrixXd& U, const Eigen::MatrixXd& V) {
  Eigen::VectorXd y(2 * U.size());
  for (Eigen::Index k = 0, i = 0; k < U.rows(); ++k)
    for (Eigen::Index p = 0; p < U.cols(); ++p) {
      y(i++) = U(k, p);
      y(i++) = V(k, p);
    }
  return y;
}

std::vector<fem::Location> locate_points(const fem::TestModel& model, const TestData& d) {
  const fem::PointLocator locator(model.mesh);
  std::vector<fem::Location> at(d.point_count());
  int outside = 0, first = -1;
  for (int p = 0; p < d.point_count(); ++p) {
    if (const auto l = locator.locate(d.points.col(p))) {
      at[p] = *l;
    } else if (outside++ == 0) {
      first = p;
    }
  }
  if (outside > 0)
    throw InputError(
        Location{d.source, 0, "experiment." + d.name + ".points"},
        std::to_string(outside) + " of " + std::to_string(d.point_count()) +
            " points are outside the specimen mesh; the first is id " + std::to_string(d.point_ids[first]) + " at (" +
            format_number(d.points(0, first)) + ", " + format_number(d.points(1, first)) + ") mm",
        "",
        model.has_conditions() ? "points within the test's mesh, in its frame (mm)"
                               : "points within the quarter model's mesh (x >= 0, y >= 0 from the axes of symmetry)");
  return at;
}

bool predict(const fem::TestModel& model, const TestData& d, const std::vector<fem::Location>& reference,
             const fem::SimulationResult& sim, const std::vector<int>* coefficients, Prediction& P,
             std::string& message) {
  const fem::Mesh& mesh = model.mesh;
  const bool jacobian = coefficients != nullptr;
  const std::vector<int> none;
  const std::vector<int>& coefficient_ = jacobian ? *coefficients : none;
  const int K = d.steps(), m = d.point_count(), n = static_cast<int>(coefficient_.size());
  if (static_cast<int>(sim.steps.size()) != K) {
    message = "test " + d.name + ": the FE returned " + std::to_string(sim.steps.size()) + " of " + std::to_string(K) +
              " steps";
    return false;
  }
  const bool force_control = model.control == fem::GripControl::force;
  const int grip_dof = force_control ? 2 * mesh.top.front() + 1 : -1;  // force control: the quarter's grip
  P.edge_displacement.resize(K);
  P.edge_force.resize(K);
  if (jacobian) {
    P.dedge_displacement_dc.setZero(K, n);
    P.dedge_force_dc.setZero(K, n);
  }
  for (int k = 0; k < K; ++k) {
    const fem::StepResult& s = sim.steps[k];
    P.edge_displacement(k) = s.edge_displacement;
    P.edge_force(k) = s.edge_force;
    if (!jacobian) continue;
    const auto nc = s.dforce_dc.size();
    bool present = s.du_dc.rows() == mesh.dofs() && s.du_dc.cols() == nc;
    for (int c : coefficient_) present = present && c < nc;
    if (!present) {
      message = "test " + d.name + ": the FE returned no sensitivities";
      return false;
    }
    for (int j = 0; j < n; ++j) {
      // docs/theory.md §7: force control moves the grip (du/dc at a top node); displacement control, the force.
      if (force_control) P.dedge_displacement_dc(k, j) = s.du_dc(grip_dof, coefficient_[j]);
      else P.dedge_force_dc(k, j) = s.dforce_dc(coefficient_[j]);
    }
  }
  if (m == 0) return true;

  P.U.resize(K, m);
  P.V.resize(K, m);
  if (jacobian) {
    P.dU_dc.setZero(K * m, n);
    P.dV_dc.setZero(K * m, n);
  }
  const int npe = fem::nodes_per_element(mesh.type);
  for (int k = 0; k < K; ++k) {
    const fem::StepResult& s = sim.steps[k];
    const bool incremental = d.field_kind == FieldKind::incremental && k > 0;
    // Incremental data: the displacement since the previous step, where the point sits in the
    // previous step's deformed mesh (docs/theory.md §7); the first step's previous state is the reference.
    const fem::StepResult* prev = incremental ? &sim.steps[k - 1] : nullptr;
    std::optional<fem::PointLocator> deformed;
    if (prev) deformed.emplace(mesh, &prev->u);
    for (int p = 0; p < m; ++p) {
      fem::Location at = reference[p];
      if (deformed) {
        const auto l = deformed->locate(d.points.col(p));
        if (!l) {
          message = "test " + d.name + ": point " + std::to_string(d.point_ids[p]) + " at (" +
                    format_number(d.points(0, p)) + ", " + format_number(d.points(1, p)) +
                    ") mm is outside the deformed mesh of step " + std::to_string(k - 1);
          return false;
        }
        at = *l;
      }
      const fem::ShapeValues sv = fem::shape(mesh.type, at.xi);
      const auto& c = mesh.connectivity[at.element];
      Vec2 value = Vec2::Zero();
      Mat2 G = Mat2::Zero(), Jm = Mat2::Zero();  // ∂Δu/∂ξ and ∂x/∂ξ of the previous configuration
      for (int a = 0; a < npe; ++a) {
        Vec2 du = s.u.segment<2>(2 * c[a]);
        if (prev) du -= prev->u.segment<2>(2 * c[a]);
        value += sv.N(a) * du;
        if (prev && jacobian) {
          G += du * sv.dN_dxi.row(a);
          Jm += (mesh.X.col(c[a]) + prev->u.segment<2>(2 * c[a])) * sv.dN_dxi.row(a);
        }
      }
      P.U(k, p) = value.x();
      P.V(k, p) = value.y();
      if (!jacobian) continue;
      const int row = k * m + p;
      const Mat2 Jm_inv = prev ? Mat2(Jm.inverse()) : Mat2(Mat2::Zero());
      for (int j = 0; j < n; ++j) {
        const int cj = coefficient_[j];
        Vec2 dvalue = Vec2::Zero(), dprev = Vec2::Zero();
        for (int a = 0; a < npe; ++a) {
          const Vec2 dua(s.du_dc(2 * c[a], cj), s.du_dc(2 * c[a] + 1, cj));
          dvalue += sv.N(a) * dua;
          if (prev) {
            const Vec2 dpa(prev->du_dc(2 * c[a], cj), prev->du_dc(2 * c[a] + 1, cj));
            dvalue -= sv.N(a) * dpa;
            dprev += sv.N(a) * dpa;
          }
        }
        // The point is fixed in space: x(ξ; u_prev) = p gives ∂ξ/∂c = −Jm⁻¹ N·∂u_prev/∂c.
        if (prev) dvalue -= G * (Jm_inv * dprev);
        P.dU_dc(row, j) = dvalue.x();
        P.dV_dc(row, j) = dvalue.y();
      }
    }
  }
  return true;
}

}  // namespace tricot::ident::detail
