// Sequence tracking: incremental, reference and automatic reference update (see sequence.hpp).
#include "tricot/dic/sequence.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <type_traits>

#include "tricot/core/error.hpp"
#include "tricot/core/format.hpp"

namespace tricot::dic {

std::string SequenceResult::brief_report() const {
  // The last frame's number + 1: `frames` may hold only the last ones (keep_frames, a resumed run).
  const std::string points = std::to_string(grid.size());
  std::string s = std::to_string(frames.empty() ? 0 : frames.back().frame + 1) + " frames, " + points + " points";
  if (!frames.empty()) {
    char z[64];
    std::snprintf(z, sizeof z, "%.4f", frames.back().mean_zncc);
    s += ": " + std::to_string(frames.back().ok) + "/" + points + " ok in the last frame, mean ZNCC " + z;
  }
  return s + ", " + format_duration(seconds);
}

const char* to_string(SequenceMode m) {
  switch (m) {
    case SequenceMode::incremental: return "incremental";
    case SequenceMode::reference: return "reference";
    case SequenceMode::automatic: return "auto";
  }
  return "unknown";
}

void SequenceOptions::validate() const {
  dic.validate();
  strain.validate();
  check_ranges(*this);
}

namespace {
const double nan = std::numeric_limits<double>::quiet_NaN();
const Vec2 nowhere(nan, nan);
}  // namespace

struct SequenceTracker::State {
  State(SequenceOptions options, Reporter rep, std::vector<GridPoint> grid, const image::Image& reference)
      : o(std::move(options)), reporter(std::move(rep)) {
    o.validate();
    result.grid = std::move(grid);
    neighbours = grid_neighbours(result.grid);
    ref = std::make_shared<const Frame>(prepare_frame(reference, o.dic.prefilter_sigma));
  }

  SequenceOptions o;
  Reporter reporter;
  SequenceResult result;
  std::vector<std::array<int, 4>> neighbours;
  std::shared_ptr<const Frame> ref, prev;  ///< the current reference image r and the previous image
  int r = 0;
  int next = 1;                            ///< the frame the next add() correlates
  std::vector<Vec2> ref_x;                 ///< positions in image r
  std::vector<Vec2> ref_sigma;             ///< σ of those positions (px), 0 in image 0
  std::vector<char> alive;                 ///< the point has a position in image r
  std::vector<PointStatus> dead;           ///< what a point that is not alive reports: why frame 0 rejected it, or lost
  std::vector<std::optional<Shape>> last;  ///< starting shapes for the next frame
  std::vector<std::optional<Shape>> fixed_last;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

  /// Correlates the alive points of image r with `cur`.
  PairResult correlate(const Frame& cur, const std::vector<std::optional<Shape>>& guesses) const {
    const int n = static_cast<int>(ref_x.size());
    std::vector<int> compact(n, -1), full;
    for (int k = 0; k < n; ++k)
      if (alive[k]) compact[k] = static_cast<int>(full.size()), full.push_back(k);
    std::vector<Vec2> c(full.size());
    std::vector<std::array<int, 4>> nb(full.size());
    std::vector<std::optional<Shape>> g(full.size());
    bool any_guess = false;
    for (std::size_t a = 0; a < full.size(); ++a) {
      const int k = full[a];
      c[a] = ref_x[k];
      for (int d = 0; d < 4; ++d) nb[a][d] = neighbours[k][d] >= 0 ? compact[neighbours[k][d]] : -1;
      g[a] = guesses[k];
      any_guess |= g[a].has_value();
    }
    PairResult compact_result =
        correlate_pair(*ref, cur, c, nb, o.dic, any_guess ? g : std::vector<std::optional<Shape>>{});
    PairResult out = compact_result;
    out.points.assign(n, PointMatch{});
    for (std::size_t a = 0; a < full.size(); ++a) out.points[full[a]] = compact_result.points[a];
    for (int k = 0; k < n; ++k)
      if (!alive[k]) out.points[k].status = dead[k];
    return out;
  }
};

SequenceTracker::SequenceTracker(const image::Image& reference, std::vector<GridPoint> grid, SequenceOptions options,
                                 Reporter reporter)
    : s_(std::make_unique<State>(std::move(options), std::move(reporter), std::move(grid), reference)) {
  State& s = *s_;
  const auto& g = s.result.grid;
  const int n = static_cast<int>(g.size());
  s.prev = s.ref;
  s.ref_x.resize(n);
  s.ref_sigma.assign(n, Vec2::Zero());
  s.alive.assign(n, 1);
  s.dead.assign(n, PointStatus::lost);
  s.last.assign(n, std::nullopt);
  s.fixed_last.assign(n, std::nullopt);
  TrackedFrame f0;
  f0.x.resize(n);
  f0.zncc.assign(n, 1.0);
  f0.status.assign(n, PointStatus::ok);
  f0.sigma.assign(n, Vec2::Zero());
  // The texture test reads every reference subset: in parallel (issue 16), then the statuses in order.
  std::vector<char> textured(n);
#pragma omp parallel for schedule(dynamic, 64) \
    num_threads(s.o.dic.threads > 0 ? std::min(s.o.dic.threads, omp_get_num_procs()) : omp_get_max_threads())
  for (int k = 0; k < n; ++k) textured[k] = has_texture(*s.ref, g[k].x, s.o.dic.icgn);
  for (int k = 0; k < n; ++k) {
    s.ref_x[k] = f0.x[k] = g[k].x;
    if (!textured[k]) {
      f0.status[k] = icgn(*s.ref, *s.ref, g[k].x, Shape::Zero(), s.o.dic.icgn).status;  // no_texture / out_of_image
      f0.zncc[k] = 0;
      s.alive[k] = 0;
      s.dead[k] = f0.status[k];
    }
  }
  std::vector<char> good(n);
  for (int k = 0; k < n; ++k) good[k] = f0.status[k] == PointStatus::ok, f0.ok += good[k];
  f0.mean_zncc = 1;
  // The reference against itself: F = I exactly where a strain can be computed (the plane fit would
  // give round-off, ±2e-16, where the reader expects 0).
  f0.strain = green_lagrange(g, f0.x, good, s.o.strain);
  for (StrainPoint& e : f0.strain)
    if (e.valid) e = StrainPoint{Mat2::Identity(), 0, 0, 0, true};
  f0.message = std::to_string(f0.ok) + "/" + std::to_string(n) + " points with texture";
  s.result.frames.push_back(std::move(f0));
}

SequenceTracker::~SequenceTracker() = default;

const TrackedFrame& SequenceTracker::add(const image::Image& next) {
  State& s = *s_;
  const auto t0 = std::chrono::steady_clock::now();
  const int k = s.next;
  const int n = static_cast<int>(s.ref_x.size());
  const auto cur = std::make_shared<const Frame>(prepare_frame(next, s.o.dic.prefilter_sigma));
  const auto since = [](std::chrono::steady_clock::time_point& t) {
    const auto now = std::chrono::steady_clock::now();
    const double d = std::chrono::duration<double>(now - t).count();
    t = now;
    return d;
  };
  auto tick = t0;
  TrackedFrame::Stages stages;
  stages.prepare = since(tick);
  const TrackedFrame& before = s.result.frames.back();

  PairResult pair = s.correlate(*cur, s.last);
  std::string note;
  if (s.o.mode == SequenceMode::automatic && s.r < k - 1) {
    int alive = 0;
    for (char a : s.alive) alive += a;
    const bool weak = pair.mean_zncc < s.o.update_zncc || (alive - pair.ok) > s.o.update_loss * alive;
    if (weak) {  // Ncorr's step analysis: the previous image becomes the reference
      std::vector<std::optional<Shape>> guess(n);
      for (int p = 0; p < n; ++p)
        if (before.status[p] == PointStatus::ok && pair.points[p].status == PointStatus::ok) {
          const Vec2 u = s.ref_x[p] + Vec2(pair.points[p].p(0), pair.points[p].p(6)) - before.x[p];
          guess[p] = translation(u(0), u(1));
        }
      s.ref = s.prev;
      s.r = k - 1;
      for (int p = 0; p < n; ++p) {
        s.alive[p] = before.status[p] == PointStatus::ok;
        s.ref_x[p] = before.x[p];
        s.ref_sigma[p] = before.sigma[p];
      }
      pair = s.correlate(*cur, guess);
      note = "reference updated to frame " + std::to_string(k - 1) + "; ";
    }
  }

  TrackedFrame f;
  f.frame = k;
  f.reference_frame = s.r;
  f.x.assign(n, nowhere);
  f.zncc.assign(n, nan);
  f.status.assign(n, PointStatus::lost);
  f.sigma.assign(n, nowhere);
  std::vector<char> good(n, 0);
  double sum = 0;
  for (int p = 0; p < n; ++p) {
    const PointMatch& m = pair.points[p];
    f.status[p] = m.status;
    if (!s.alive[p]) continue;
    f.zncc[p] = m.zncc;
    if (m.status == PointStatus::ok) {
      f.x[p] = s.ref_x[p] + Vec2(m.p(0), m.p(6));
      f.sigma[p] = (s.ref_sigma[p].cwiseAbs2() + m.sigma.cwiseAbs2()).cwiseSqrt();
      good[p] = 1;
      ++f.ok;
      sum += m.zncc;
    }
  }
  f.mean_zncc = f.ok ? sum / f.ok : 0;
  stages.correlate = since(tick);
  std::vector<Vec2> X(s.result.grid.size());
  for (int p = 0; p < n; ++p) X[p] = s.result.grid[p].x;
  f.strain = green_lagrange(s.result.grid, f.x, good, s.o.strain);
  f.message = note + pair.message;
  stages.strain = since(tick);

  // Fixed-point incremental field between the previous image and this one (before the state moves on).
  if (s.o.fixed_point_fields) {
    IncrementField inc;
    inc.from = k - 1;
    inc.to = k;
    bool any = false;
    for (const auto& g : s.fixed_last) any |= g.has_value();
    const PairResult fp = correlate_pair(*s.prev, *cur, X, s.neighbours, s.o.dic,
                                         any ? s.fixed_last : std::vector<std::optional<Shape>>{});
    inc.u.assign(n, nowhere);
    inc.sigma.assign(n, nowhere);
    inc.zncc.resize(n);
    inc.status.resize(n);
    for (int p = 0; p < n; ++p) {
      const PointMatch& m = fp.points[p];
      inc.zncc[p] = m.zncc;
      inc.status[p] = m.status;
      if (m.status == PointStatus::ok) {
        inc.u[p] = Vec2(m.p(0), m.p(6));
        inc.sigma[p] = m.sigma;
        s.fixed_last[p] = m.p;
      }
    }
    if (!s.o.keep_frames) s.result.increments.clear();
    s.result.increments.push_back(std::move(inc));
    stages.increments = since(tick);
  }

  // Move on.
  if (s.o.mode == SequenceMode::incremental) {
    s.ref = cur;
    s.r = k;
    for (int p = 0; p < n; ++p) {
      s.alive[p] = good[p];
      s.ref_x[p] = f.x[p];
      s.ref_sigma[p] = f.sigma[p];
      s.last[p] = good[p] ? std::optional<Shape>(pair.points[p].p) : std::nullopt;
    }
  } else {
    for (int p = 0; p < n; ++p)
      if (good[p]) s.last[p] = pair.points[p].p;
  }
  s.prev = cur;
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  f.stages = stages;
  s.result.frames.push_back(std::move(f));
  if (!s.o.keep_frames) s.result.frames.erase(s.result.frames.begin(), s.result.frames.end() - 1);
  ++s.next;
  const TrackedFrame& done = s.result.frames.back();
  char detail[160];
  std::snprintf(detail, sizeof detail, "frame %d: %d/%d ok, mean ZNCC %.4f, ref %d", k, done.ok, n, done.mean_zncc,
                done.reference_frame);
  s.reporter.info(std::string(detail) + " — " + done.message);
  return done;
}

const SequenceResult& SequenceTracker::result() {
  State& s = *s_;
  SequenceResult& r = s.result;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - s.start).count();
  const TrackedFrame& last = r.frames.back();
  r.termination = last.ok > 0 || s.next == 1 ? SequenceTermination::completed : SequenceTermination::all_lost;
  r.message = std::to_string(s.next) + " frames, " + to_string(s.o.mode) + " mode; " + std::to_string(last.ok) + "/" +
              std::to_string(r.grid.size()) + " points ok in the last frame";
  if (r.termination == SequenceTermination::all_lost) r.message += " (every point was lost)";
  return r;
}

// Checkpoints: the State's fields in a fixed order, each number as its bytes (this machine's byte
// order: a checkpoint resumes a run on the machine that made it).
namespace {

constexpr char kMagic[] = "tricot-dic-sequence-1";

struct Writer {
  std::string bytes;
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put_vec2s(const std::vector<Vec2>& v) {
    for (const Vec2& x : v) put(x(0)), put(x(1));
  }
  void put_shapes(const std::vector<std::optional<Shape>>& v) {
    for (const auto& p : v) {
      put(static_cast<char>(p.has_value()));
      if (p)
        for (int i = 0; i < p->size(); ++i) put((*p)(i));
    }
  }
  void put_string(const std::string& t) {
    put(static_cast<std::uint64_t>(t.size()));
    bytes += t;
  }
};

struct Reader {
  const std::string& bytes;
  std::size_t at = 0;
  [[noreturn]] void fail() const {
    throw InputError(Location{"", 0, "resume"}, "not a DIC checkpoint of this run (truncated or of another grid)",
                     std::to_string(bytes.size()) + " bytes", "the checkpoint a killed run of the same settings left");
  }
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    if (at + sizeof(T) > bytes.size()) fail();
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  std::vector<Vec2> get_vec2s(std::size_t n) {
    std::vector<Vec2> v(n);
    for (Vec2& x : v) x(0) = get<double>(), x(1) = get<double>();
    return v;
  }
  std::vector<std::optional<Shape>> get_shapes(std::size_t n) {
    std::vector<std::optional<Shape>> v(n);
    for (auto& p : v)
      if (get<char>()) {
        Shape q;
        for (int i = 0; i < q.size(); ++i) q(i) = get<double>();
        p = q;
      }
    return v;
  }
  std::string get_string() {
    const auto size = get<std::uint64_t>();
    if (size > bytes.size() - at) fail();
    std::string t = bytes.substr(at, size);
    at += size;
    return t;
  }
};

SequenceResumePoint read_header(Reader& in) {
  if (in.get_string() != kMagic) in.fail();
  SequenceResumePoint p;
  p.next_frame = in.get<int>();
  p.reference_frame = in.get<int>();
  if (p.next_frame < 1 || p.reference_frame < 0 || p.reference_frame >= p.next_frame) in.fail();
  return p;
}

}  // namespace

std::string SequenceTracker::checkpoint() const {
  const State& s = *s_;
  Writer out;
  out.put_string(kMagic);
  out.put(s.next);
  out.put(s.r);
  const std::size_t n = s.ref_x.size();
  out.put(static_cast<std::uint64_t>(n));
  for (const GridPoint& g : s.result.grid) out.put(g.x(0)), out.put(g.x(1));
  out.put_vec2s(s.ref_x);
  out.put_vec2s(s.ref_sigma);
  for (char a : s.alive) out.put(a);
  for (PointStatus d : s.dead) out.put(d);
  out.put_shapes(s.last);
  out.put_shapes(s.fixed_last);
  const TrackedFrame& f = s.result.frames.back();
  out.put(f.frame);
  out.put(f.reference_frame);
  out.put_vec2s(f.x);
  for (double z : f.zncc) out.put(z);
  for (PointStatus st : f.status) out.put(st);
  for (const StrainPoint& e : f.strain)
    out.put(e.F(0, 0)), out.put(e.F(0, 1)), out.put(e.F(1, 0)), out.put(e.F(1, 1)), out.put(e.exx), out.put(e.eyy),
        out.put(e.exy), out.put(static_cast<char>(e.valid));
  out.put_vec2s(f.sigma);
  out.put(f.ok);
  out.put(f.mean_zncc);
  out.put(f.seconds);
  out.put_string(f.message);
  return out.bytes;
}

SequenceResumePoint SequenceTracker::resume_point(const std::string& checkpoint) {
  Reader in{checkpoint};
  return read_header(in);
}

SequenceTracker::SequenceTracker(const image::Image& reference, const image::Image& previous,
                                 std::vector<GridPoint> grid, SequenceOptions options, const std::string& checkpoint,
                                 Reporter reporter)
    : s_(std::make_unique<State>(std::move(options), std::move(reporter), std::move(grid), reference)) {
  State& s = *s_;
  Reader in{checkpoint};
  const SequenceResumePoint at = read_header(in);
  s.next = at.next_frame;
  s.r = at.reference_frame;
  const std::size_t n = s.result.grid.size();
  if (in.get<std::uint64_t>() != n) in.fail();
  for (const GridPoint& g : s.result.grid)
    if (in.get<double>() != g.x(0) || in.get<double>() != g.x(1)) in.fail();
  s.ref_x = in.get_vec2s(n);
  s.ref_sigma = in.get_vec2s(n);
  s.alive.resize(n);
  for (char& a : s.alive) a = in.get<char>();
  s.dead.resize(n);
  for (PointStatus& d : s.dead) d = in.get<PointStatus>();
  s.last = in.get_shapes(n);
  s.fixed_last = in.get_shapes(n);
  TrackedFrame f;
  f.frame = in.get<int>();
  f.reference_frame = in.get<int>();
  f.x = in.get_vec2s(n);
  f.zncc.resize(n);
  for (double& z : f.zncc) z = in.get<double>();
  f.status.resize(n);
  for (PointStatus& st : f.status) st = in.get<PointStatus>();
  f.strain.resize(n);
  for (StrainPoint& e : f.strain) {
    e.F(0, 0) = in.get<double>(), e.F(0, 1) = in.get<double>(), e.F(1, 0) = in.get<double>(),
           e.F(1, 1) = in.get<double>();
    e.exx = in.get<double>(), e.eyy = in.get<double>(), e.exy = in.get<double>();
    e.valid = in.get<char>() != 0;
  }
  f.sigma = in.get_vec2s(n);
  f.ok = in.get<int>();
  f.mean_zncc = in.get<double>();
  f.seconds = in.get<double>();
  f.message = in.get_string();
  if (in.at != checkpoint.size() || f.frame != s.next - 1) in.fail();
  s.result.frames.push_back(std::move(f));
  s.prev = s.r == s.next - 1 ? s.ref : std::make_shared<const Frame>(prepare_frame(previous, s.o.dic.prefilter_sigma));
}

SequenceResult track_sequence(const std::vector<image::Image>& images, const Roi& roi, const SequenceOptions& options,
                              Reporter reporter) {
  options.validate();
  if (images.empty()) throw InputError(Location{}, "no images", "0", "at least one");
  auto grid = make_grid(roi, images[0].width, images[0].height, options.dic.icgn.subset_size, options.dic.step);
  SequenceTracker t(images[0], std::move(grid), options, reporter);
  for (std::size_t k = 1; k < images.size(); ++k) {
    t.add(images[k]);
    reporter.report({"dic", k, images.size() - 1, ""});
  }
  return t.result();
}

}  // namespace tricot::dic
