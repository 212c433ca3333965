// Dof map and colored parallel assembly (docs/theory.md §4, §6, §7).
#include "assembly.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>

#include <omp.h>

namespace tricot::fem::detail {

namespace {

// Conditions per named boundary (TestModel::conditions): fixed, series or tied dofs, a later condition
// winning; the force boundary's component plays the quarter's top u_y (DofMap::top_y).
void map_conditions(const TestModel& test, DofMap& d) {
  const Mesh& m = test.mesh;
  for (size_t i = 0; i < test.conditions.size(); ++i) {
    const BoundaryCondition& c = test.conditions[i];
    const int s = c.values.empty() ? -1 : static_cast<int>(d.series_values.size());
    if (s >= 0) d.series_values.push_back(c.values);
    auto set = [&](int n, int eq, double tie) {
      const int k = 2 * n + c.component;
      d.eq[k] = eq, d.tie[k] = tie;
      d.series[k] = eq < 0 ? s : -1;
      d.anchor[k] = eq < 0 ? -1 : s;
      d.scale[k] = c.proportional ? m.X(c.component, n) : 1.0;
    };
    if (c.tie > 0) {
      for (const auto& [n, tie] : test.tie_stiffness(i)) set(n, 0, tie);
    } else {
      for (int n : m.boundary(c.boundary)) set(n, -1, 0.0);
    }
  }
  if (!test.force_boundary.empty())
    for (int n : m.boundary(test.force_boundary)) d.top_y.push_back(2 * n + test.force_component);
}

}  // namespace

DofMap make_dof_map(const TestModel& test) {
  const Mesh& m = test.mesh;
  const int ndof = m.dofs();
  DofMap d;
  d.eq.assign(ndof, 0);  // 0 = free for now, −1 = prescribed, −2 = shared grip
  d.grip.assign(ndof, 0);
  d.guide.assign(ndof, 0.0);
  d.tie.assign(ndof, 0.0);
  d.series.assign(ndof, -1);
  d.anchor.assign(ndof, -1);
  d.scale.assign(ndof, 1.0);
  for (const std::string& name : test.resultant_boundaries()) d.resultant_nodes.push_back(m.boundary(name));
  if (test.has_conditions()) {
    map_conditions(test, d);
    for (int k = 0; k < ndof; ++k)
      if (d.eq[k] == 0) d.eq[k] = d.equations++;
    return d;
  }
  const double W = m.X.row(0).maxCoeff();
  for (int n : m.left) d.eq[2 * n] = -1;        // symmetry: u_x = 0
  for (int n : m.bottom) d.eq[2 * n + 1] = -1;  // symmetry: u_y = 0
  for (size_t i = 0; i < m.top.size(); ++i) {
    const int n = m.top[i];
    d.top_y.push_back(2 * n + 1);
    if (test.control == GripControl::displacement) {
      d.eq[2 * n + 1] = -1;
      d.grip[2 * n + 1] = 1;
    } else {
      d.eq[2 * n + 1] = -2;
    }
    if (test.grip_holds_x) d.eq[2 * n] = -1;
    if (test.grip_holds_x && test.grip_follows_guide && test.side == SideEdge::guide)
      d.guide[2 * n] = m.X(0, n) / W;  // the pantograph clamp: u_x = c·X/W
    if (test.grip_holds_x && test.grip_tie_stiffness > 0 && m.X(0, n) > 1e-12 * W) {  // x = 0: symmetry
      // Clip ties: lumped over the node's share of the grip, tapered to zero at the side edge.
      const double x = m.X(0, n);
      const double left = i > 0 ? x - m.X(0, m.top[i - 1]) : 0;
      const double right = i + 1 < m.top.size() ? m.X(0, m.top[i + 1]) - x : 0;
      const double taper = test.grip_taper > 0 ? std::clamp((W - x) / test.grip_taper, 0.0, 1.0) : 1.0;
      d.eq[2 * n] = 0;
      d.tie[2 * n] = test.grip_tie_stiffness * 0.5 * (left + right) * taper;
    }
  }
  const double guide_end = m.X.row(1).maxCoeff() - test.guide_gap;
  for (size_t i = 0; i < m.right.size(); ++i) {
    const int n = m.right[i];
    // The rig's guide ends guide_gap short of the grip (docs/theory.md §6): the nodes above it are free.
    const double y = m.X(1, n);
    const bool guided = test.guide_gap <= 0 || y <= guide_end + 1e-9 * guide_end;
    if (test.side == SideEdge::guide && guided) d.right_x.push_back(2 * n);
    if (test.side == SideEdge::guide && guided && test.guide_tie_stiffness > 0) {
      // Lumped tie: stiffness per length × the node's share of the edge, tapered near the guide's end.
      const double below = i > 0 ? y - m.X(1, m.right[i - 1]) : 0;
      const double above = i + 1 < m.right.size() ? std::min(m.X(1, m.right[i + 1]), guide_end) - y : 0;
      const double taper = test.guide_taper > 0 ? std::clamp((guide_end - y) / test.guide_taper, 0.0, 1.0) : 1.0;
      d.tie[2 * n] = test.guide_tie_stiffness * 0.5 * (below + std::max(above, 0.0)) * taper;
      d.guide[2 * n] = 1;
      if (d.eq[2 * n] < 0) d.eq[2 * n] = 0;  // the top-right node: the guide's tie, not the clip
      continue;
    }
    if (test.side == SideEdge::guide && guided) {
      d.tie[2 * n] = 0;  // a rigid guide wins over a clip tie at the top-right node
      d.eq[2 * n] = -1;
      d.guide[2 * n] = 1;
    }
  }
  for (int k = 0; k < ndof; ++k) {
    if (d.eq[k] == 0) {
      d.eq[k] = d.equations++;
    } else if (d.eq[k] == -2) {
      if (d.master < 0) d.master = d.equations++;
      d.eq[k] = d.master;
    }
  }
  return d;
}

namespace {

// A series' value at step parameter t: 0 at t = 0, values[k] at t = k + 1, linear in between.
double series_value(const std::vector<double>& values, double t) {
  if (!(t > 0)) return 0;
  const double last = static_cast<double>(values.size());
  if (t >= last) return values.back();
  const int k = static_cast<int>(t);  // t in [k, k + 1)
  const double before = k == 0 ? 0.0 : values[k - 1];
  return before + (t - k) * (values[k] - before);
}

}  // namespace

void expand(const DofMap& dofs, const Eigen::VectorXd& z, const Load& load, Eigen::VectorXd& u) {
  const int ndof = static_cast<int>(dofs.eq.size());
  u.resize(ndof);
  for (int k = 0; k < ndof; ++k) {
    if (dofs.eq[k] >= 0) {
      u(k) = z(dofs.eq[k]);
    } else {
      u(k) = load.d * dofs.grip[k] + load.c * dofs.guide[k];
      if (dofs.series[k] >= 0) u(k) += dofs.scale[k] * series_value(dofs.series_values[dofs.series[k]], load.t);
    }
  }
}

Eigen::VectorXd series_displacements(const DofMap& dofs, double t) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(dofs.eq.size()));
  for (size_t k = 0; k < dofs.eq.size(); ++k)
    if (dofs.series[k] >= 0)
      u(static_cast<Eigen::Index>(k)) = dofs.scale[k] * series_value(dofs.series_values[dofs.series[k]], t);
  return u;
}

double tie_anchor(const DofMap& dofs, int k, const Load& load) {
  const double c = load.c * dofs.guide[k];
  return dofs.anchor[k] < 0 ? c : c + dofs.scale[k] * series_value(dofs.series_values[dofs.anchor[k]], load.t);
}

namespace {

// Quadrature points per assembly from which threads are tried. On the benchmark strip (3024 points, a
// 0.25 ms assembly, 8 colors) two threads saved ≤ 0.1 ms per assembly on an idle machine, but on the
// loaded 2-core machine a preempted thread stalls every color barrier: the 35-step run took 146–433 ms
// threaded against 96–105 ms serial (docs/validation.md). Threads are tried from ~10× that size.
constexpr int kParallelPoints = 30000;
constexpr int kProbes = 4;  // timed assemblies (alternating serial, threaded) before the choice

int element_dof(const Mesh& m, int e, int i) { return 2 * m.connectivity[e][i / 2] + i % 2; }

}  // namespace

Assembler::Assembler(const TestModel& test, const DofMap& dofs, const Law& law)
    : test_(test), dofs_(dofs), law_(law), Q_(material_axes(test.material_angle)) {
  const Mesh& m = test.mesh;
  const int ne = m.elements();
  D_ = 2 * nodes_per_element(m.type);
  coefficient_count_ = static_cast<int>(law.coefficients().size());
  geometry_.reserve(ne);
  for (int e = 0; e < ne; ++e) geometry_.push_back(element_geometry(m, e));

  // Fixed pattern of the free-free block.
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(ne) * D_ * D_);
  for (int e = 0; e < ne; ++e)
    for (int i = 0; i < D_; ++i)
      for (int j = 0; j < D_; ++j) {
        const int qi = dofs.eq[element_dof(m, e, i)], qj = dofs.eq[element_dof(m, e, j)];
        if (qi >= 0 && qj >= 0) t.emplace_back(qi, qj, 0.0);
      }
  pattern_.resize(dofs.equations, dofs.equations);
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();

  // Scatter map: element pair (i, j) -> position of (eq_i, eq_j) in valuePtr().
  slot_.assign(static_cast<size_t>(ne) * D_ * D_, -1);
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  for (int e = 0; e < ne; ++e)
    for (int i = 0; i < D_; ++i)
      for (int j = 0; j < D_; ++j) {
        const int qi = dofs.eq[element_dof(m, e, i)], qj = dofs.eq[element_dof(m, e, j)];
        if (qi < 0 || qj < 0) continue;
        const int* p = std::lower_bound(inner + outer[qj], inner + outer[qj + 1], qi);
        slot_[(static_cast<size_t>(e) * D_ + i) * D_ + j] = static_cast<int>(p - inner);
      }

  // The free-row × series-column block, for the predictor of a series increment.
  std::vector<Eigen::Triplet<double>> ts;
  for (int e = 0; e < ne; ++e)
    for (int i = 0; i < D_; ++i)
      for (int j = 0; j < D_; ++j) {
        const int qi = dofs.eq[element_dof(m, e, i)], dj = element_dof(m, e, j);
        if (qi >= 0 && dofs.series[dj] >= 0) ts.emplace_back(qi, dj, 0.0);
      }
  pattern_fs_.resize(dofs.equations, m.dofs());
  pattern_fs_.setFromTriplets(ts.begin(), ts.end());
  pattern_fs_.makeCompressed();
  series_entries_.resize(ts.empty() ? 0 : ne);
  for (int e = 0; e < ne && !ts.empty(); ++e)
    for (int i = 0; i < D_; ++i)
      for (int j = 0; j < D_; ++j) {
        const int qi = dofs.eq[element_dof(m, e, i)], dj = element_dof(m, e, j);
        if (qi < 0 || dofs.series[dj] < 0) continue;
        const int* begin = pattern_fs_.innerIndexPtr() + pattern_fs_.outerIndexPtr()[dj];
        const int* end = pattern_fs_.innerIndexPtr() + pattern_fs_.outerIndexPtr()[dj + 1];
        const int* p = std::lower_bound(begin, end, qi);
        series_entries_[e].push_back({i, j, static_cast<int>(p - pattern_fs_.innerIndexPtr())});
      }

  // Per element: dofs, equations, and the few local dofs that feed g_grip, g_guide and h_top.
  dof_.resize(static_cast<size_t>(ne) * D_);
  eq_.resize(dof_.size());
  grip_local_.resize(ne), guide_local_.resize(ne), top_local_.resize(ne);
  std::vector<char> top(m.dofs(), 0);
  for (int k : dofs.top_y) top[k] = 1;
  for (int e = 0; e < ne; ++e)
    for (int i = 0; i < D_; ++i) {
      const int d = element_dof(m, e, i);
      dof_[e * D_ + i] = d, eq_[e * D_ + i] = dofs.eq[d];
      if (dofs.grip[d]) grip_local_[e].push_back(i);
      if (dofs.guide[d] != 0 && dofs.eq[d] < 0) guide_local_[e].push_back(i);
      if (top[d]) top_local_[e].push_back(i);
    }

  // Greedy coloring: elements conflict when they share a node or an equation (the shared grip).
  const int N = m.nodes();
  std::vector<std::vector<int>> users(N + 1);
  auto resources = [&](int e) {
    std::vector<int> r;
    for (int a = 0; a < D_ / 2; ++a) r.push_back(m.connectivity[e][a]);
    for (int i = 0; i < D_; ++i)
      if (dofs.master >= 0 && dofs.eq[element_dof(m, e, i)] == dofs.master) r.push_back(N);
    return r;
  };
  for (int e = 0; e < ne; ++e)
    for (int r : resources(e)) users[r].push_back(e);
  std::vector<int> color(ne, -1);
  for (int e = 0; e < ne; ++e) {
    std::vector<char> used;
    for (int r : resources(e))
      for (int o : users[r])
        if (color[o] >= 0) {
          if (color[o] >= static_cast<int>(used.size())) used.resize(color[o] + 1, 0);
          used[color[o]] = 1;
        }
    int c = 0;
    while (c < static_cast<int>(used.size()) && used[c]) ++c;
    color[e] = c;
    if (c >= static_cast<int>(colors_.size())) colors_.resize(c + 1);
    colors_[c].push_back(e);
  }
}

bool Assembler::assemble(const Eigen::VectorXd& u, const LawRequest& req, Assembled& a, const Load& load) const {
  const Mesh& m = test_.mesh;
  const int ndof = m.dofs(), neq = dofs_.equations;
  a.f.setZero(ndof);
  if (req.tangent) {
    if (a.K.nonZeros() != pattern_.nonZeros() || a.K.rows() != neq) a.K = pattern_;
    std::fill(a.K.valuePtr(), a.K.valuePtr() + a.K.nonZeros(), 0.0);
    a.g_grip.setZero(neq);
    a.g_guide.setZero(neq);
    a.h_top.setZero(neq);
    if (a.K_fs.nonZeros() != pattern_fs_.nonZeros() || a.K_fs.rows() != neq) a.K_fs = pattern_fs_;
    std::fill(a.K_fs.valuePtr(), a.K_fs.valuePtr() + a.K_fs.nonZeros(), 0.0);
  }
  if (req.sensitivities) a.df_dc.setZero(ndof, coefficient_count_);
  if (req.tangent) a.symmetric = true;  // else K and its flag stay those of the last tangent
  a.status = ElementStatus::ok;
  a.element = -1;
  a.min_detF = INFINITY;

  std::atomic<bool> failed{false};
  double* K = req.tangent ? a.K.valuePtr() : nullptr;
  double* K_fs = req.tangent ? a.K_fs.valuePtr() : nullptr;

  // Threads pay off on an idle machine but cost a scheduler slice per color barrier on a loaded one:
  // the first kProbes tangent assemblies alternate serial and threaded (the first threaded one also
  // starts the thread pool), and the way with the faster best time is kept.
  const bool try_threads = omp_get_max_threads() > 1 && m.elements() * geometry_.front().points >= kParallelPoints;
  const int probe = req.tangent && try_threads && threaded_ < 0 ? probes_++ : -1;
  const bool parallel = try_threads && (probe >= 0 ? probe % 2 == 1 : threaded_ == 1);
  const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel if (parallel)
  {
    LawOutput lo;
    ElementResponse r;
    bool symmetric = true;
    double min_detF = INFINITY;
    for (const auto& elements : colors_) {
#pragma omp for schedule(static)
      for (size_t k = 0; k < elements.size(); ++k) {
        if (failed.load(std::memory_order_relaxed)) continue;
        const int e = elements[k];
        ElementStatus s;
        try {
          s = element_response(geometry_[e], element_displacements(m, e, u), law_, Q_, req, lo, r);
        } catch (...) {
          s = ElementStatus::non_finite;
        }
        min_detF = std::min(min_detF, r.min_detF);
        if (s != ElementStatus::ok) {
#pragma omp critical(tricot_fem_assembly_failure)
          if (a.element < 0 || e < a.element) a.status = s, a.element = e, a.min_detF = r.min_detF;
          failed = true;
          continue;
        }
        const int* dof = &dof_[static_cast<size_t>(e) * D_];
        const int* eq = &eq_[static_cast<size_t>(e) * D_];
        for (int i = 0; i < D_; ++i) a.f(dof[i]) += r.f(i);
        if (req.sensitivities)
          for (int i = 0; i < D_; ++i) a.df_dc.row(dof[i]) += r.df_dc.row(i);
        if (!req.tangent) continue;
        symmetric = symmetric && r.symmetric_tangent;
        const int* slot = &slot_[static_cast<size_t>(e) * D_ * D_];
        for (int i = 0; i < D_; ++i)
          for (int j = 0; j < D_; ++j)
            if (slot[i * D_ + j] >= 0) K[slot[i * D_ + j]] += r.K(i, j);
        for (int j : grip_local_[e])
          for (int i = 0; i < D_; ++i)
            if (eq[i] >= 0) a.g_grip(eq[i]) += r.K(i, j);
        for (int j : guide_local_[e])
          for (int i = 0; i < D_; ++i)
            if (eq[i] >= 0) a.g_guide(eq[i]) += r.K(i, j) * dofs_.guide[dof[j]];
        for (int i : top_local_[e])
          for (int j = 0; j < D_; ++j)
            if (eq[j] >= 0) a.h_top(eq[j]) += r.K(i, j);
        if (!series_entries_.empty())
          for (const auto& [i, j, slot_fs] : series_entries_[e]) K_fs[slot_fs] += r.K(i, j);
      }
    }
#pragma omp critical(tricot_fem_assembly_reduce)
    {
      if (req.tangent) a.symmetric = a.symmetric && symmetric;
      if (a.status == ElementStatus::ok) a.min_detF = std::min(a.min_detF, min_detF);
    }
  }
  // Ties: f += t (u − anchor), ∂R/∂u = t, ∂R/∂c = −t w (anchor = c w on the quarter).
  for (int k = 0; k < ndof && !failed; ++k) {
    const double t = dofs_.tie[k];
    if (t == 0) continue;
    a.f(k) += t * (u(k) - tie_anchor(dofs_, k, load));
    if (req.tangent) {
      a.K.coeffRef(dofs_.eq[k], dofs_.eq[k]) += t;
      a.g_guide(dofs_.eq[k]) -= t * dofs_.guide[k];
    }
  }
  if (probe >= 0) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double& best = probe_seconds_[probe % 2];
    best = probe < 2 ? seconds : std::min(best, seconds);
    if (probe == kProbes - 1) threaded_ = probe_seconds_[1] < probe_seconds_[0] ? 1 : 0;
  }
  return !failed;
}

}  // namespace tricot::fem::detail
