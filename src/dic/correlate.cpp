// Seeds + reliability-guided propagation + IC-GN over a set of points (see correlate.hpp).
#include "tricot/dic/correlate.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>

#include "tricot/core/error.hpp"
#include "tricot/dic/seed.hpp"

namespace tricot::dic {

void DicOptions::validate() const {
  icgn.validate();
  check_ranges(*this);
  for (const Vec2& s : seeds)
    if (!s.allFinite())
      throw InputError(Location{"", 0, "dic.seeds"}, "out of range", "a non-finite coordinate", "finite px");
}

namespace {

/// Wide seed searches (seed.hpp) per image pair: each costs about a second on a large image, and a
/// pair where two of them fail (a blank or unrelated image) will not be saved by a third.
constexpr int kMaxWideSearches = 2;
/// IC-GN iterations allowed from a caller's guess (see correlate_pair).
constexpr int kGuessIterations = 12;

/// Per-point bookkeeping of the propagation.
enum class State : unsigned char { open, done, given_up };

class Propagation {
 public:
  Propagation(const Frame& ref, const Frame& cur, const std::vector<Vec2>& centres,
              const std::vector<std::array<int, 4>>& nb, const DicOptions& o, PairResult& r)
      : reference_(ref), current_(cur), centres_(centres), neighbours_(nb), options_(o), result_(r),
        state_(centres.size(), State::open), tries_(centres.size(), 0), guess_failed_(centres.size(), 0) {}

  /// Marks k as computed: good points feed the queue, bad ones may be retried once from another parent.
  void settle(int k, const PointMatch& m) {
    PointMatch& best = result_.points[k];
    if (m.status == PointStatus::ok || best.status == PointStatus::not_computed ||
        (best.status != PointStatus::ok && m.zncc > best.zncc))
      best = m;
    if (m.status == PointStatus::ok) {
      state_[k] = State::done;
      queue_.push({m.zncc, k});
    } else if (++tries_[k] >= 2 || m.status == PointStatus::no_texture) {
      state_[k] = State::given_up;
    }
  }

  /// A failure from a caller's guess: propagation may still try the point once from a neighbour, and
  /// a seed may still be placed on it (every guess can be wrong: a step unlike the one before).
  void record_failure(int k, const PointMatch& m) {
    result_.points[k] = m;
    tries_[k] = 1;
    guess_failed_[k] = 1;
  }

  bool open(int k) const { return state_[k] == State::open; }
  /// Never attempted from a neighbour or as a seed: the only points a seed may be placed on.
  bool untried(int k) const { return state_[k] == State::open && tries_[k] == guess_failed_[k]; }
  bool ok(int k) const { return state_[k] == State::done; }
  /// How many points are good so far.
  int good() const { return static_cast<int>(std::count(state_.begin(), state_.end(), State::done)); }

  /// Pops the most reliable points in rounds of `batch` and computes their open neighbours in parallel,
  /// each from the shape of the parent that reached it (shifted to the neighbour's centre).
  void run() {
    std::vector<std::pair<int, int>> tasks;  // (point, parent)
    std::vector<char> claimed(centres_.size(), 0);
    std::vector<PointMatch> out;
    while (!queue_.empty()) {
      tasks.clear();
      for (int b = 0; b < options_.batch && !queue_.empty(); ++b) {
        const int parent = queue_.top().second;
        queue_.pop();
        for (int n : neighbours_[parent])
          if (n >= 0 && open(n) && !claimed[n]) claimed[n] = 1, tasks.emplace_back(n, parent);
      }
      out.resize(tasks.size());
      result_.round_tasks.push_back(static_cast<int>(tasks.size()));
      // one task at a time: a round holds ~40 subsets of ~35 µs, and chunks of 4 left a thread idle for
      // up to 4 subsets at each round's barrier (issue 16)
#pragma omp parallel for schedule(dynamic, 1)
      for (int t = 0; t < static_cast<int>(tasks.size()); ++t) {
        const auto [k, parent] = tasks[t];
        out[t] = icgn(reference_, current_, centres_[k],
                      shift_shape(result_.points[parent].p, centres_[k] - centres_[parent]), options_.icgn);
      }
      for (std::size_t t = 0; t < tasks.size(); ++t) {
        claimed[tasks[t].first] = 0;
        settle(tasks[t].first, out[t]);
      }
    }
  }

 private:
  const Frame &reference_, &current_;
  const std::vector<Vec2>& centres_;
  const std::vector<std::array<int, 4>>& neighbours_;
  const DicOptions& options_;
  PairResult& result_;
  std::vector<State> state_;
  std::vector<unsigned char> tries_;
  std::vector<unsigned char> guess_failed_;  ///< 1 when the caller's guess failed (not a try of ours)
  std::priority_queue<std::pair<double, int>> queue_;
};

/// Whether the shape `pj` of a neighbour, carried over by `d` to a point, predicts that point's
/// displacement within kConsistency px.
constexpr double kConsistency = 1.0;  ///< px: far above the measurement error, far below a false match's offset
bool agree(const Shape& pj, const Shape& pk, const Vec2& d) {
  const Vec2 predicted = warp_displacement(pj, d);
  return (predicted - Vec2(pk(0), pk(6))).norm() < kConsistency;
}

int nearest_untried(const std::vector<Vec2>& c, const Vec2& x, const Propagation& prop) {
  int best = -1;
  double d = 1e300;
  for (int k = 0; k < static_cast<int>(c.size()); ++k)
    if (prop.untried(k) && (c[k] - x).squaredNorm() < d) d = (c[k] - x).squaredNorm(), best = k;
  return best;
}

std::string fmt_point(const Vec2& x) {
  char b[64];
  std::snprintf(b, sizeof b, "(%.0f, %.0f)", x(0), x(1));
  return b;
}

}  // namespace

PairResult correlate_pair(const Frame& ref, const Frame& cur, const std::vector<Vec2>& centres,
                          const std::vector<std::array<int, 4>>& neighbours, const DicOptions& o,
                          const std::vector<std::optional<Shape>>& guesses) {
  o.validate();
  const auto t0 = std::chrono::steady_clock::now();
  const int n = static_cast<int>(centres.size());
  PairResult r;
  r.points.assign(n, PointMatch{});
  if (o.threads > 0) omp_set_num_threads(std::min(o.threads, omp_get_num_procs()));  // more than the cores never helps
  Propagation prop(ref, cur, centres, neighbours, o, r);
  std::string message;

  // 1. Points with a guess: all at once, in parallel.
  if (!guesses.empty()) {
    // A good guess converges in a few iterations; one that has not after kGuessIterations is far off,
    // and propagation from a good neighbour will do better than the full iteration budget.
    IcgnOptions quick = o.icgn;
    quick.max_iterations = std::min(quick.max_iterations, kGuessIterations);
    std::vector<PointMatch> out(n);
#pragma omp parallel for schedule(dynamic, 8)
    for (int k = 0; k < n; ++k)
      if (guesses[k]) out[k] = icgn(ref, cur, centres[k], *guesses[k], quick);
    // A guess far from the truth may converge on a look-alike subset elsewhere (self-similar speckle
    // matches at ZNCC ≈ 0.9): a point is kept only when a good neighbour's shape, carried over to it,
    // agrees with it. The others are left to propagation from the consistent ones.
    std::vector<char> consistent(n, 0);
    for (int k = 0; k < n; ++k)
      if (guesses[k] && out[k].status == PointStatus::ok)
        for (int j : neighbours[k])
          if (j >= 0 && guesses[j] && out[j].status == PointStatus::ok &&
              agree(out[j].p, out[k].p, centres[k] - centres[j])) {
            consistent[k] = 1;
            break;
          }
    int with_guess = 0, good = 0;
    for (int k = 0; k < n; ++k)
      if (guesses[k]) {
        ++with_guess;
        if (out[k].status == PointStatus::ok && !consistent[k]) out[k].status = PointStatus::inconsistent;
        good += out[k].status == PointStatus::ok;
        // a failure from a guess leaves the point open for propagation
        if (out[k].status == PointStatus::ok || out[k].status == PointStatus::no_texture) prop.settle(k, out[k]);
        else prop.record_failure(k, out[k]);
      }
    message = std::to_string(good) + "/" + std::to_string(with_guess) + " from guesses";
  }
  // 2. Propagate from what is good; 3. seed whatever remains unreached.
  prop.run();
  // Seeds: the user's first, then the untried point nearest the centroid of the untried points
  // (blank ones are skipped without spending an attempt).
  std::size_t user = 0;
  std::vector<int> failed_seeds;
  int wide_tries = 0;
  while (r.seeds_tried < o.max_seeds) {
    int k = -1;
    if (user < o.seeds.size()) {
      k = nearest_untried(centres, o.seeds[user++], prop);
    } else {
      Vec2 centroid = Vec2::Zero();
      int count = 0;
      for (int q = 0; q < n; ++q)
        if (prop.untried(q)) ++count, centroid += centres[q];
      if (count == 0) break;
      centroid /= count;
      while ((k = nearest_untried(centres, centroid, prop)) >= 0 && !has_texture(ref, centres[k], o.icgn))
        prop.settle(k, icgn(ref, cur, centres[k], Shape::Zero(), o.icgn));  // no_texture or out_of_image
    }
    if (k < 0) break;
    ++r.seeds_tried;
    Vec2 predicted = Vec2::Zero();
    if (!guesses.empty() && guesses[k]) predicted = Vec2((*guesses[k])(0), (*guesses[k])(6));
    PointMatch m;
    if (!has_texture(ref, centres[k], o.icgn)) {
      m = icgn(ref, cur, centres[k], Shape::Zero(), o.icgn);  // reports no_texture or out_of_image
    } else if (const SeedGuess g = seed_guess(ref, cur, centres[k], o.icgn.subset_size, o.search_radius, predicted);
               g.found) {
      m = icgn(ref, cur, centres[k], g.p, o.icgn);
      if (m.status != PointStatus::ok) {  // the satellites' gradient may mislead: try the rigid shift
        const PointMatch rigid = icgn(ref, cur, centres[k], translation(g.p(0), g.p(6)), o.icgn);
        if (rigid.status == PointStatus::ok || rigid.zncc > m.zncc) m = rigid;
      }
    } else {
      m.status = PointStatus::low_correlation;
    }
    // Everything else starts from a seed: it must correlate clearly better than a look-alike subset.
    const auto weak = [&](PointMatch& pm) {
      if (pm.status == PointStatus::ok && pm.zncc < o.seed_min_zncc) pm.status = PointStatus::low_correlation;
    };
    weak(m);
    bool wide = false;
    // Nothing measured yet in this pair and the local search failed: look over the whole image with
    // stretched templates (a large one-step motion). Once one point is good, propagation does the rest.
    if (m.status != PointStatus::ok && m.status != PointStatus::no_texture && m.status != PointStatus::out_of_image &&
        wide_tries < kMaxWideSearches && prop.good() == 0) {
      ++wide_tries;
      if (const SeedGuess w = wide_seed_guess(ref, cur, centres[k], o.icgn.subset_size); w.found) {
        PointMatch mw = icgn(ref, cur, centres[k], w.p, o.icgn);
        weak(mw);
        if (mw.status == PointStatus::ok || mw.zncc > m.zncc) m = mw, wide = mw.status == PointStatus::ok;
      }
    }
    message += (message.empty() ? "" : "; ") + std::string("seed ") + std::to_string(r.seeds_tried) + " at " +
               fmt_point(centres[k]) + ": " + to_string(m.status) + (wide ? " (wide search)" : "");
    prop.settle(k, m);
    if (m.status != PointStatus::ok && prop.open(k)) prop.settle(k, m);  // a seed is not retried
    if (m.status != PointStatus::ok && m.status != PointStatus::no_texture) failed_seeds.push_back(k);
    prop.run();
  }
  // Points that propagation never reached (their neighbours all failed) and failed seeds: one attempt
  // from the nearest good point's shape, so that each reports its own reason (out_of_image, ...).
  std::vector<int> good;
  for (int k = 0; k < n; ++k)
    if (r.points[k].status == PointStatus::ok) good.push_back(k);
  std::vector<int> left;
  for (int k = 0; k < n; ++k)
    if (r.points[k].status == PointStatus::not_computed) left.push_back(k);
  for (int k : failed_seeds)
    if (r.points[k].status != PointStatus::ok) left.push_back(k);
  std::vector<PointMatch> last(left.size());
#pragma omp parallel for schedule(dynamic, 4)
  for (int a = 0; a < static_cast<int>(left.size()); ++a) {
    const int k = left[a];
    int parent = -1;
    double d = 1e300;
    for (int q : good)
      if ((centres[q] - centres[k]).squaredNorm() < d) d = (centres[q] - centres[k]).squaredNorm(), parent = q;
    if (parent >= 0) {
      last[a] = icgn(ref, cur, centres[k], shift_shape(r.points[parent].p, centres[k] - centres[parent]), o.icgn);
    } else if (!has_texture(ref, centres[k], o.icgn)) {
      last[a] = icgn(ref, cur, centres[k], Shape::Zero(), o.icgn);
    }
  }
  for (std::size_t a = 0; a < left.size(); ++a)
    if (last[a].status != PointStatus::not_computed) r.points[left[a]] = last[a];
  double sum = 0;
  for (const PointMatch& m : r.points)
    if (m.status == PointStatus::ok) ++r.ok, sum += m.zncc;
  r.mean_zncc = r.ok ? sum / r.ok : 0;
  r.message =
      std::to_string(r.ok) + "/" + std::to_string(n) + " points ok" + (message.empty() ? "" : " (" + message + ")");
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace tricot::dic
