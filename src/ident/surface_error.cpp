// Eq. (9) error (docs/theory.md §9).
#include "tricot/ident/surface_error.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include <Eigen/QR>

#include "tricot/core/error.hpp"

namespace tricot::ident {

void StrainDomain::validate() const {
  auto check = [](const char* key, double lo, double hi) {
    if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi)
      throw InputError(Location{"", 0, std::string("eq9.practical.") + key}, "not a strain interval",
                       "[" + format_number(lo) + ", " + format_number(hi) + "]", "finite bounds, min <= max");
  };
  check("course", eC_min, eC_max);
  check("wale", eW_min, eW_max);
}

Eq9Error eq9_error(const std::vector<SurfacePoint>& points, const std::function<double(double, double)>& identified,
                   const StrainDomain& practical) {
  practical.validate();
  Eq9Error e;
  double sum = 0, sum_p = 0;
  double cmin = 1e300, cmax = -1e300, wmin = 1e300, wmax = -1e300;
  for (const SurfacePoint& p : points) {
    if (p.force == 0 || !std::isfinite(p.force)) continue;
    const double d = std::abs(identified(p.eC, p.eW) - p.force) / std::abs(p.force);
    sum += d, ++e.points_whole;
    cmin = std::min(cmin, p.eC), cmax = std::max(cmax, p.eC), wmin = std::min(wmin, p.eW), wmax = std::max(wmax, p.eW);
    if (practical.contains(p.eC, p.eW)) sum_p += d, ++e.points_practical;
  }
  if (e.points_whole == 0)
    throw InputError(Location{"", 0, "eq9.points"}, "no experimental point with a non-zero force",
                     std::to_string(points.size()) + " points", "at least one point with F != 0");
  if (e.points_practical == 0)
    throw InputError(Location{"", 0, "eq9.practical"}, "the practical domain holds no experimental point",
                     "course [" + format_number(practical.eC_min) + ", " + format_number(practical.eC_max) +
                         "] x wale [" + format_number(practical.eW_min) + ", " + format_number(practical.eW_max) + "]",
                     "a domain that meets the data (course [" + format_number(cmin) + ", " + format_number(cmax) +
                         "], wale [" + format_number(wmin) + ", " + format_number(wmax) + "])");
  e.whole = sum / e.points_whole;
  e.practical = sum_p / e.points_practical;
  return e;
}

std::optional<TestSurfacePoints> test_surface_points(const fem::TestModel& model, const TestData& data, int nearest) {
  constexpr double kAngleTol = 1e-9;  // degrees: the two pulls are exactly 0 or 90 in a project
  TestSurfacePoints out;
  if (std::abs(model.material_angle) <= kAngleTol) out.force = SurfaceForce::wale;
  else if (std::abs(model.material_angle - 90) <= kAngleTol) out.force = SurfaceForce::course;
  else return std::nullopt;
  const int n = data.point_count();
  if (data.edge_force.empty() || data.field_kind != FieldKind::cumulative || n < 3 || data.u.rows() != data.steps())
    return std::nullopt;
  // The points nearest the centre (the quarter model's origin).
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return data.points.col(a).norm() < data.points.col(b).norm(); });
  const int m = std::clamp(nearest, 3, n);
  Eigen::MatrixXd A(m, 3);
  for (int i = 0; i < m; ++i) A.row(i) << 1, data.points(0, order[i]), data.points(1, order[i]);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 3) return std::nullopt;  // collinear points: no gradient
  const double width = 2 * model.mesh.X.row(0).maxCoeff();
  for (int k = 0; k < data.steps(); ++k) {
    Eigen::VectorXd bu(m), bv(m);
    for (int i = 0; i < m; ++i) bu(i) = data.u(k, order[i]), bv(i) = data.v(k, order[i]);
    const Eigen::Vector3d gu = qr.solve(bu), gv = qr.solve(bv);
    Eigen::Matrix2d F;
    F << 1 + gu(1), gu(2), gv(1), 1 + gv(2);
    const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
    // Wale pulled (angle 0): course along x. Course pulled (90): course along y.
    const bool course_along_x = out.force == SurfaceForce::wale;
    const double eC = course_along_x ? E(0, 0) : E(1, 1), eW = course_along_x ? E(1, 1) : E(0, 0);
    out.points.push_back({eC, eW, data.edge_force[k] / width});
  }
  const bool course_pulled = out.force == SurfaceForce::course;
  for (SurfacePoint& p : out.points) p.held = course_pulled ? out.points.front().eW : out.points.front().eC;
  return out;
}

int held_levels(const std::vector<SurfacePoint>& points, double tolerance) {
  std::vector<double> h;
  for (const SurfacePoint& p : points)
    if (std::isfinite(p.held)) h.push_back(p.held);
  std::sort(h.begin(), h.end());
  int levels = h.empty() ? 0 : 1;
  for (std::size_t i = 1; i < h.size(); ++i) levels += h[i] - h[i - 1] > tolerance;
  return levels;
}

Restriction restrict_to_domain(const std::vector<fem::TestModel>& models, const Experiment& experiment,
                               const StrainDomain& domain, int nearest) {
  const Location key{"", 0, "data.domain"};
  Restriction out;
  for (std::size_t t = 0; t < experiment.tests.size() && t < models.size(); ++t) {
    const TestData& data = experiment.tests[t];
    const auto p = test_surface_points(models[t], data, nearest);
    if (!p || p->points.empty())
      throw InputError(
          key, "test '" + data.name + "' has no centre strains to restrict by",
          "material_angle " + format_number(models[t].material_angle),
          "a test pulled along wale (0) or course (90) with a grip force and a cumulative field of >= 3 points");
    const bool course_pulled = p->force == SurfaceForce::course;
    const auto pulled_of = [&](const SurfacePoint& q) { return course_pulled ? q.eC : q.eW; };
    RestrictedTest r{data.name, data.steps(), 0, course_pulled ? p->points[0].eW : p->points[0].eC,
                     pulled_of(p->points[0])};
    const double held_min = course_pulled ? domain.eW_min : domain.eC_min,
                 held_max = course_pulled ? domain.eW_max : domain.eC_max;
    const double pulled_max = course_pulled ? domain.eC_max : domain.eW_max;
    if (r.held >= held_min && r.held <= held_max)
      while (r.kept < r.steps && pulled_of(p->points[r.kept]) <= pulled_max) r.pulled = pulled_of(p->points[r.kept++]);
    out.tests.push_back(r);
    if (r.kept == 0) continue;
    fem::TestModel m = models[t];
    TestData d = data;
    const int n = r.kept;
    // A single guide value without a setting moves with the load (c · load / last load): keep its path.
    if (m.guide.size() == 1 && m.guide_setting_steps == 0 && !m.loads.empty() && n < static_cast<int>(m.loads.size())) {
      const double c = m.guide[0], last = m.loads.back();
      m.guide.assign(m.loads.begin(), m.loads.end());
      for (double& g : m.guide) g = c * g / last;
    }
    if (m.guide.size() == m.loads.size() && m.guide.size() > 1) m.guide.resize(n);
    m.loads.resize(n), d.loads.resize(n);
    for (auto* v : {&d.edge_displacement, &d.edge_force})
      if (!v->empty()) v->resize(n);
    for (auto* M : {&d.u, &d.v, &d.sigma_u, &d.sigma_v})
      if (M->rows() > 0) M->conservativeResize(n, Eigen::NoChange);
    out.models.push_back(std::move(m));
    out.experiment.tests.push_back(std::move(d));
  }
  if (out.models.empty())
    throw InputError(key, "the domain keeps no test",
                     "course [" + format_number(domain.eC_min) + ", " + format_number(domain.eC_max) + "] x wale [" +
                         format_number(domain.eW_min) + ", " + format_number(domain.eW_max) + "]",
                     "a domain that holds the held strain and the first step of some test");
  return out;
}

}  // namespace tricot::ident
