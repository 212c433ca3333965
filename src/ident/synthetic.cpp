// Synthetic measurements from an FE run, with optional Gaussian noise.
#include "tricot/ident/synthetic.hpp"

#include <cmath>
#include <numeric>
#include <random>

#include "predict.hpp"
#include "tricot/core/error.hpp"

namespace tricot::ident {

TestData measure(const fem::TestModel& model, const fem::SimulationResult& sim, const Eigen::Matrix2Xd& points,
                 std::vector<int> ids, FieldKind kind) {
  if (!sim.usable())
    throw InputError(Location{"", 0, "test." + model.name}, "the simulation did not converge: " + sim.message);
  TestData d;
  d.name = model.name;
  d.loads = model.loads;
  d.field_kind = kind;
  d.points = points;
  if (ids.empty()) {
    ids.resize(points.cols());
    std::iota(ids.begin(), ids.end(), 0);
  }
  d.point_ids = std::move(ids);
  const auto reference = detail::locate_points(model, d);
  detail::Prediction P;
  std::string message;
  if (!detail::predict(model, d, reference, sim, nullptr, P, message))
    throw InputError(Location{"", 0, "test." + model.name + ".points"}, message);
  d.edge_displacement.assign(P.edge_displacement.data(), P.edge_displacement.data() + P.edge_displacement.size());
  d.edge_force.assign(P.edge_force.data(), P.edge_force.data() + P.edge_force.size());
  if (points.cols() > 0) {
    d.u = P.U;
    d.v = P.V;
  }
  return d;
}

void add_noise(TestData& d, const Sigma& sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 1);
  if (sigma.edge_displacement > 0)
    for (double& x : d.edge_displacement) x += sigma.edge_displacement * g(rng);
  if (sigma.edge_force > 0)
    for (double& x : d.edge_force) x += sigma.edge_force * g(rng);
  if (sigma.field > 0) {
    for (Eigen::Index i = 0; i < d.u.size(); ++i) d.u.data()[i] += sigma.field * g(rng);
    for (Eigen::Index i = 0; i < d.v.size(); ++i) d.v.data()[i] += sigma.field * g(rng);
  }
  d.sigma = sigma;
}

Sigma rms_fraction(const TestData& d, double fraction) {
  auto rms = [](const double* x, std::size_t n) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += x[i] * x[i];
    return n ? std::sqrt(s / n) : 0.0;
  };
  Sigma s;
  s.edge_displacement = fraction * rms(d.edge_displacement.data(), d.edge_displacement.size());
  s.edge_force = fraction * rms(d.edge_force.data(), d.edge_force.size());
  const double su = rms(d.u.data(), d.u.size()), sv = rms(d.v.data(), d.v.size());
  s.field = fraction * std::sqrt((su * su * d.u.size() + sv * sv * d.v.size()) /
                                 std::max<Eigen::Index>(1, d.u.size() + d.v.size()));
  return s;
}

}  // namespace tricot::ident
