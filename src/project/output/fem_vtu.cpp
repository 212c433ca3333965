#include "tricot/project/fem_vtu.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "tricot/fem/element.hpp"
#include "tricot/fem/wrinkling.hpp"

namespace tricot::project {

io::VtuGrid fem_vtu_grid(const fem::Mesh& mesh, const Eigen::VectorXd& u, const fem::Law& law,
                         double material_angle_deg) {
  io::VtuGrid g;
  const int n = mesh.nodes(), per = fem::nodes_per_element(mesh.type);
  g.points.reserve(3 * n);
  io::VtuField disp{"displacement", 3, {}};
  disp.values.reserve(3 * n);
  for (int a = 0; a < n; ++a) {
    g.points.insert(g.points.end(), {mesh.X(0, a) + u(2 * a), mesh.X(1, a) + u(2 * a + 1), 0.0});
    disp.values.insert(disp.values.end(), {u(2 * a), u(2 * a + 1), 0.0});
  }
  // Our node orders (corners CCW, then the mid-sides from edge 0-1 on) are VTK's.
  switch (mesh.type) {
    case fem::ElementType::Q4: g.cell_type = io::VtkCell::quad; break;
    case fem::ElementType::Q8: g.cell_type = io::VtkCell::quadratic_quad; break;
    case fem::ElementType::T3: g.cell_type = io::VtkCell::triangle; break;
    case fem::ElementType::T6: g.cell_type = io::VtkCell::quadratic_triangle; break;
  }
  g.connectivity.reserve(per * mesh.elements());
  for (const auto& c : mesh.connectivity) g.connectivity.insert(g.connectivity.end(), c.begin(), c.begin() + per);

  io::VtuField sigma{"cauchy_stress", 9, {}}, strain{"green_lagrange_strain", 9, {}};
  // The smallest acoustic eigenvalue over the element's points (N/mm): ≤ 0 where the law has lost
  // strong ellipticity and the membrane can localise (fem::strong_ellipticity).
  io::VtuField ellipticity{"ellipticity", 1, {}};
  // A tension-field law (docs/theory/fabric.md §8): the area fractions of the element that are
  // wrinkled and slack, and the wrinkles' mean direction (current configuration; the doubled-angle
  // mean, so that t and −t agree), zero where nothing wrinkles.
  const bool wrinkling = dynamic_cast<const fem::WrinklingLaw*>(&law) != nullptr;
  io::VtuField wrinkled{"wrinkled_fraction", 1, {}}, slack{"slack_fraction", 1, {}},
      direction{"wrinkle_direction", 3, {}};
  const std::vector<fem::ElementWrinkles> wrinkles = fem::element_wrinkles(mesh, law, material_angle_deg, u);
  const Mat2 Q = fem::material_axes(material_angle_deg);
  fem::LawOutput out;
  const fem::LawRequest req{true, false};
  for (int e = 0; e < mesh.elements(); ++e) {
    const fem::ElementGeometry geo = fem::element_geometry(mesh, e);
    const fem::ElementVector ue = fem::element_displacements(mesh, e, u);
    Mat2 s = Mat2::Zero(), E = Mat2::Zero();
    double E33 = 0, area = 0, lowest = std::numeric_limits<double>::infinity();
    for (int q = 0; q < geo.points; ++q) {
      const Mat2 F = fem::deformation_gradient(geo, q, ue);
      fem::LawInput in;
      in.F = F;
      in.Q = Q;
      in.region = geo.region;
      double l3 = std::numeric_limits<double>::quiet_NaN();
      Mat2 sq = Mat2::Constant(std::numeric_limits<double>::quiet_NaN());
      if (F.determinant() > 0) {
        law.evaluate(in, req, out);
        sq = fem::Law::cauchy(F, out.P);
        l3 = out.lambda3;
        lowest = std::min(lowest, out.A.allFinite() ? fem::strong_ellipticity(out.A).min_eigenvalue
                                                    : std::numeric_limits<double>::quiet_NaN());
      } else {
        lowest = std::numeric_limits<double>::quiet_NaN();
      }
      const double w = geo.dA0[q];
      s += w * sq;
      E += w * 0.5 * (F.transpose() * F - Mat2::Identity());
      E33 += w * 0.5 * (l3 * l3 - 1);
      area += w;
    }
    s /= area, E /= area, E33 /= area;
    sigma.values.insert(sigma.values.end(), {s(0, 0), s(0, 1), 0, s(1, 0), s(1, 1), 0, 0, 0, 0});
    strain.values.insert(strain.values.end(), {E(0, 0), E(0, 1), 0, E(1, 0), E(1, 1), 0, 0, 0, E33});
    ellipticity.values.push_back(lowest);
    if (wrinkling) {
      const fem::ElementWrinkles& r = wrinkles[std::size_t(e)];
      wrinkled.values.push_back(r.wrinkled);
      slack.values.push_back(r.slack);
      const bool any = r.wrinkled > 0;
      direction.values.insert(direction.values.end(),
                              {any ? std::cos(r.angle) : 0.0, any ? std::sin(r.angle) : 0.0, 0.0});
    }
  }
  g.point_data = {std::move(disp)};
  g.cell_data = {std::move(sigma), std::move(strain), std::move(ellipticity)};
  if (wrinkling) {
    g.cell_data.push_back(std::move(wrinkled));
    g.cell_data.push_back(std::move(slack));
    g.cell_data.push_back(std::move(direction));
  }
  return g;
}

}  // namespace tricot::project
