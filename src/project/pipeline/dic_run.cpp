// tricot dic's pipeline (see dic_run.hpp).
#include "tricot/project/dic_run.hpp"

#include "tricot/project/output_dir.hpp"

#include <fmt/format.h>

#include <fmt/ranges.h>

#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <span>
#include <string_view>

#include "tricot/dic/overlay.hpp"
#include "tricot/image/image.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/vtu.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

namespace {

std::string overlay_name(int frame) { return fmt::format("frame_{:04d}.png", frame); }

// The tables' numbers keep the precision of what they measure: pixels to 1e-5, ZNCC to 1e-6,
// specimen millimetres to 1e-6, strains to 7 digits, standard deviations to 4.
constexpr io::CsvFormat kPx = io::CsvFormat::decimals(5), kZncc = io::CsvFormat::decimals(6),
                        kMm = io::CsvFormat::decimals(6), kStrain = io::CsvFormat::significant(7),
                        kSigma = io::CsvFormat::significant(4);

constexpr std::string_view kPointsColumns[] = {"frame", "id",     "x0",  "y0",  "x",   "y",       "u",      "v",
                                               "zncc",  "status", "exx", "eyy", "exy", "sigma_x", "sigma_y"};
// vsg_px (issue 16): the strains' virtual strain gauge, dic::virtual_strain_gauge, the same on every row.
constexpr std::string_view kFramesColumns[] = {"frame",  "image",     "reference_frame", "ok",
                                               "points", "mean_zncc", "seconds",         "vsg_px"};
constexpr std::string_view kIncrementsColumns[] = {"from", "to",   "id",     "x",       "y",      "u",
                                                   "v",    "zncc", "status", "sigma_x", "sigma_y"};
constexpr std::string_view kSpecimenColumns[] = {"frame", "id", "X0",  "Y0",  "X",   "Y",
                                                 "UX",    "UY", "EXX", "EYY", "EXY", "status"};

std::string frames_row(const dic::TrackedFrame& f, std::size_t points, const std::string& image, int vsg_px) {
  io::CsvWriter csv;
  csv.integer(f.frame).text(image).integer(f.reference_frame).integer(f.ok).integer(static_cast<long long>(points));
  csv.number(f.mean_zncc, kZncc).number(f.seconds, io::CsvFormat::decimals(3));
  if (vsg_px > 0) csv.integer(vsg_px);
  else csv.text("");
  return csv.end_row().take();
}

std::string increments_rows(const std::vector<dic::GridPoint>& grid, const dic::IncrementField& inc) {
  io::CsvWriter csv;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const bool ok = inc.status[k] == dic::PointStatus::ok;
    const Vec2 sg = ok && k < inc.sigma.size() ? inc.sigma[k] : Vec2::Constant(std::nan(""));
    csv.integer(inc.from).integer(inc.to).integer(static_cast<long long>(k));
    csv.number_or_empty(grid[k].x(0), kPx).number_or_empty(grid[k].x(1), kPx);
    csv.number_or_empty(inc.u[k](0), kPx).number_or_empty(inc.u[k](1), kPx);
    csv.number_or_empty(ok ? inc.zncc[k] : NAN, kZncc).text(dic::to_string(inc.status[k]));
    csv.number_or_empty(sg(0), kSigma).number_or_empty(sg(1), kSigma).end_row();
  }
  return csv.take();
}

std::string specimen_rows(const std::vector<dic::GridPoint>& grid, const dic::TrackedFrame& f,
                          const dic::PhysicalFrame& p) {
  io::CsvWriter csv;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const bool ok = f.status[k] == dic::PointStatus::ok;
    const Vec2 X0 = p.point(grid[k].x);
    const Vec2 X = ok ? p.point(f.x[k]) : Vec2::Constant(NAN);
    const Vec2 U = ok ? p.vector(f.x[k] - grid[k].x) : Vec2::Constant(NAN);
    const dic::StrainPoint& e = f.strain[k];
    Mat2 E = Mat2::Constant(NAN);
    if (e.valid) E = p.tensor((Mat2() << e.exx, e.exy, e.exy, e.eyy).finished());
    csv.integer(f.frame).integer(static_cast<long long>(k));
    for (double v : {X0(0), X0(1), X(0), X(1), U(0), U(1)}) csv.number_or_empty(v, kMm);
    for (double v : {E(0, 0), E(1, 1), E(0, 1)}) csv.number_or_empty(v, kStrain);
    csv.text(dic::to_string(f.status[k])).end_row();
  }
  return csv.take();
}

}  // namespace

std::string points_rows(const std::vector<dic::GridPoint>& grid, const dic::TrackedFrame& f) {
  // One buffer for the frame, each cell formatted in place (issue 16: the table is written every frame).
  io::CsvWriter csv;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const Vec2 X = grid[k].x, x = f.x[k];
    const bool ok = f.status[k] == dic::PointStatus::ok;
    const dic::StrainPoint& e = f.strain[k];
    const Vec2 sg = ok && k < f.sigma.size() ? f.sigma[k] : Vec2::Constant(NAN);
    csv.integer(f.frame).integer(static_cast<long long>(k));
    csv.number_or_empty(X(0), kPx).number_or_empty(X(1), kPx);
    csv.number_or_empty(ok ? x(0) : NAN, kPx).number_or_empty(ok ? x(1) : NAN, kPx);
    csv.number_or_empty(ok ? x(0) - X(0) : NAN, kPx).number_or_empty(ok ? x(1) - X(1) : NAN, kPx);
    csv.number_or_empty(ok ? f.zncc[k] : NAN, kZncc).text(dic::to_string(f.status[k]));
    csv.number_or_empty(e.valid ? e.exx : NAN, kStrain).number_or_empty(e.valid ? e.eyy : NAN, kStrain);
    csv.number_or_empty(e.valid ? e.exy : NAN, kStrain);
    csv.number_or_empty(sg(0), kSigma).number_or_empty(sg(1), kSigma).end_row();
  }
  return csv.take();
}

io::VtuGrid fields_vtu(const std::vector<dic::GridPoint>& grid, const dic::TrackedFrame& f, int vsg_px) {
  io::VtuGrid g;
  const std::size_t n = grid.size();
  g.points.reserve(3 * n);
  for (const dic::GridPoint& p : grid) g.points.insert(g.points.end(), {p.x(0), p.x(1), 0.0});
  // Quads between grid neighbours (i, j), (i+1, j), (i+1, j+1), (i, j+1): counter-clockwise on screen
  // with y down is clockwise in (x, y); the order only flips the normal, which a 2-D field ignores.
  if (n > 0) {
    int i0 = grid[0].i, i1 = i0, j0 = grid[0].j, j1 = j0;
    for (const dic::GridPoint& p : grid)
      i0 = std::min(i0, p.i), i1 = std::max(i1, p.i), j0 = std::min(j0, p.j), j1 = std::max(j1, p.j);
    const long long W = i1 - i0 + 1;
    std::vector<int> at(static_cast<std::size_t>(W * (j1 - j0 + 1)), -1);
    const auto index = [&](int i, int j) { return static_cast<std::size_t>((j - j0) * W + (i - i0)); };
    for (std::size_t k = 0; k < n; ++k) at[index(grid[k].i, grid[k].j)] = static_cast<int>(k);
    for (int j = j0; j < j1; ++j)
      for (int i = i0; i < i1; ++i) {
        const int a = at[index(i, j)], b = at[index(i + 1, j)], c = at[index(i + 1, j + 1)], d = at[index(i, j + 1)];
        if (a >= 0 && b >= 0 && c >= 0 && d >= 0) g.connectivity.insert(g.connectivity.end(), {a, b, c, d});
      }
  }
  io::VtuField u{"displacement", 3, {}}, exx{"exx", 1, {}}, eyy{"eyy", 1, {}}, exy{"exy", 1, {}}, zncc{"zncc", 1, {}},
      status{"status", 1, {}};
  u.values.reserve(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const bool ok = f.status[k] == dic::PointStatus::ok;
    const Vec2 d = ok ? Vec2(f.x[k] - grid[k].x) : Vec2::Constant(NAN);
    u.values.insert(u.values.end(), {d(0), d(1), ok ? 0.0 : NAN});
    const dic::StrainPoint& e = f.strain[k];
    exx.values.push_back(e.valid ? e.exx : NAN);
    eyy.values.push_back(e.valid ? e.eyy : NAN);
    exy.values.push_back(e.valid ? e.exy : NAN);
    zncc.values.push_back(ok ? f.zncc[k] : NAN);
    status.values.push_back(static_cast<double>(f.status[k]));
  }
  g.point_data = {std::move(u), std::move(exx), std::move(eyy), std::move(exy), std::move(zncc), std::move(status)};
  if (vsg_px > 0) g.field_data = {io::VtuField{"vsg_px", 1, {double(vsg_px)}}};  // issue 16
  return g;
}

DicSpec dic_spec(const std::string& file, const DicFlags& a) {
  const io::Node root = file.empty() ? io::default_config(dic_schema()) : io::read_config(dic_schema(), file);
  DicSpec spec = DicSpec::from_config(root, file.empty() ? fs::path() : fs::path(file).parent_path());
  DicTable& d = spec.dic;
  dic::SequenceOptions& o = spec.sequence;
  if (a.subset) o.dic.icgn.subset_size = *a.subset, d.origin.set_by_flag("subset_size", "--subset");
  if (a.step) o.dic.step = *a.step, d.origin.set_by_flag("step", "--step");
  if (!a.mode.empty()) {
    d.origin.set_by_flag("mode", "--mode");
    try {
      o.mode = value_of(option_of(&dic::SequenceOptions::mode), a.mode);
    } catch (const InputError& e) {
      spec.rethrow(e);
    }
  }
  if (!a.roi.empty()) {
    d.roi = parse_roi_flag(a.roi);
    d.roi_polygon.clear();
    d.roi_mask.clear();
    d.origin.set_by_flag("roi", "--roi");
  }
  return spec;
}

namespace {

/// A table that grows frame by frame in the staging folder. A resumed run cuts it back to the size
/// the checkpoint recorded (dropping the rows of a frame the kill interrupted) and appends.
class GrowingFile {
 public:
  GrowingFile(fs::path path, std::span<const std::string_view> columns, std::uint64_t resume_size)
      : path_(std::move(path)) {
    io::CsvWriter csv;
    for (std::string_view c : columns) csv.text(c);
    const std::string header = csv.end_row().take();
    std::error_code ec;
    fs::create_directories(path_.parent_path(), ec);
    if (resume_size > 0) {
      fs::resize_file(path_, resume_size, ec);
      if (ec) throw FileError({path_.string(), 0, ""}, "cannot resume: " + ec.message());
      out_.open(path_, std::ios::binary | std::ios::app);
    } else {
      out_.open(path_, std::ios::binary | std::ios::trunc);
      out_ << header;
    }
    if (!out_) throw FileError({path_.string(), 0, ""}, "cannot write");
    size_ = resume_size > 0 ? resume_size : header.size();
  }
  void append(const std::string& text) {
    out_.write(text.data(), static_cast<std::streamsize>(text.size()));
    size_ += text.size();
  }
  /// Flushes to the file: what the checkpoint records must be on disk before it.
  std::uint64_t flush() {
    out_.flush();
    if (!out_) throw FileError({path_.string(), 0, ""}, "write failed (disk full?)");
    return size_;
  }
  void close() { flush(), out_.close(); }

 private:
  fs::path path_;
  std::ofstream out_;
  std::uint64_t size_ = 0;
};

/// The run's checkpoint in the staging folder: which run it belongs to, how long each table was after
/// the last complete frame, and the tracker's state (dic::SequenceTracker::checkpoint).
constexpr const char* kCheckpointName = "resume.bin";
constexpr const char* kCheckpointMagic = "tricot-dic-run-1\n";

struct RunCheckpoint {
  std::string fingerprint;
  std::vector<std::uint64_t> sizes;  ///< points, frames, increments, specimen (0 = not written)
  int lost_at = -1;
  std::string tracker;
};

std::string encode(const RunCheckpoint& c) {
  std::string s = kCheckpointMagic;
  const auto put = [&](std::uint64_t v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(c.fingerprint.size());
  s += c.fingerprint;
  put(c.sizes.size());
  for (std::uint64_t v : c.sizes) put(v);
  put(static_cast<std::uint64_t>(static_cast<std::int64_t>(c.lost_at)));
  put(c.tracker.size());
  s += c.tracker;
  return s;
}

std::optional<RunCheckpoint> decode(const std::string& s) {
  std::size_t at = 0;
  const auto take = [&](std::size_t n, std::string* to) {
    if (at + n > s.size()) return false;
    if (to) *to = s.substr(at, n);
    at += n;
    return true;
  };
  std::string magic;
  if (!take(std::string(kCheckpointMagic).size(), &magic) || magic != kCheckpointMagic) return std::nullopt;
  const auto get = [&](std::uint64_t* v) {
    std::string b;
    if (!take(sizeof *v, &b)) return false;
    std::memcpy(v, b.data(), sizeof *v);
    return true;
  };
  RunCheckpoint c;
  std::uint64_t n = 0;
  if (!get(&n) || !take(n, &c.fingerprint) || !get(&n) || n > 16) return std::nullopt;
  c.sizes.resize(n);
  for (auto& v : c.sizes)
    if (!get(&v)) return std::nullopt;
  std::uint64_t lost = 0;
  if (!get(&lost)) return std::nullopt;
  c.lost_at = static_cast<int>(static_cast<std::int64_t>(lost));
  if (!get(&n) || !take(n, &c.tracker) || at != s.size()) return std::nullopt;
  return c;
}

/// What must not change between a killed run and its resumption: the images and every setting that
/// shapes the files.
std::string fingerprint(const DicSpec& spec, const std::vector<std::string>& images, std::size_t points) {
  const DicTable& d = spec.dic;
  const dic::SequenceOptions& o = spec.sequence;
  const dic::IcgnOptions& g = o.dic.icgn;
  std::string s = fmt::format(
      "subset {} step {} mode {} order {} roi [{}] polygon [{}] mask {} seeds [{}] radius {} max_seeds {} seed_zncc {} "
      "iterations {} tolerance {} min_zncc {} texture {} prefilter {} update {} {} batch {}; strain {} {}; "
      "physical {} [{}] {} {}; overlays {} {} [{}] {} {} increments {} fields {} {}; points {}; weight {}\n",
      g.subset_size, o.dic.step, word_of(option_of(&dic::SequenceOptions::mode), o.mode),
      word_of(option_of(&dic::IcgnOptions::order), g.order), fmt::join(d.roi, ","), fmt::join(d.roi_polygon, ","),
      d.roi_mask, fmt::join(d.seeds, ","), o.dic.search_radius, o.dic.max_seeds, o.dic.seed_min_zncc, g.max_iterations,
      g.tolerance, g.min_zncc, g.min_texture, o.dic.prefilter_sigma, o.update_zncc, o.update_loss, o.dic.batch,
      o.strain.window, o.strain.min_fraction, spec.physical.mm_per_px, fmt::join(spec.physical.centre_px, ","),
      spec.physical.angle_deg, spec.physical.y_up, spec.output.overlays, spec.output.overlay_every,
      fmt::join(spec.output.panels, ","), spec.overlay.panel_width, spec.overlay.zncc_floor, spec.output.increments,
      spec.output.fields, spec.output.fields_every, points, g.weight_sigma);
  for (const std::string& i : images) s += i + "\n";
  return s;
}

/// The longest period (px) at which dic::strain_transfer is below 90 %, by a scan in 0.5 px steps.
double strain_p90(int subset, int step, int window) {
  double p = 6.0 * dic::virtual_strain_gauge(subset, step, window);
  while (p > 2 && dic::strain_transfer(p, subset, step, window) >= 0.9) p -= 0.5;
  return p + 0.5;
}

/// Frame 0, every `every`-th frame and the last.
bool wanted(int frame, int every, int last) { return frame % every == 0 || frame == last; }

std::string fields_name(int frame) { return fmt::format("fields/frame_{:04d}.vtu", frame); }

/// Seconds since `t`, and `t` moved to now.
double lap(std::chrono::steady_clock::time_point& t) {
  const auto now = std::chrono::steady_clock::now();
  const double d = std::chrono::duration<double>(now - t).count();
  t = now;
  return d;
}

}  // namespace

std::string DicStageSeconds::brief_report() const {
  std::string s;
  for (const auto& [name, v] : {std::pair{"check", check},
                                {"decode", decode},
                                {"prepare", prepare},
                                {"correlate", correlate},
                                {"strain", strain},
                                {"increments", increments},
                                {"tables", tables},
                                {"overlays", overlays},
                                {"fields", fields},
                                {"checkpoint", checkpoint}})
    if (v > 0) s += fmt::format("{}{} {:.2f} s", s.empty() ? "" : ", ", name, v);
  return s;
}

DicRun run_dic(const DicSpec& spec, const std::vector<std::string>& images, const fs::path& out_dir, const Log& log,
               const DicRunOptions& options) {
  for (const auto& img : images) {
    std::error_code ec;
    if (!fs::exists(img, ec)) throw FileError({img, 0, ""}, "image not found");
  }
  {
    std::error_code ec;
    if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec))
      throw FileError({out_dir.string(), 0, ""}, "output folder is a file");
  }

  DicRun run;
  std::vector<std::string>& warnings = run.warnings;
  OutputDir output(out_dir, "dic", options.resume);  // written in staging, published at the end (issue 14)
  const fs::path staged = output.staging();
  const image::LoadedImage ref = image::load_image(images[0]);
  if (!ref.warning.empty()) warnings.push_back(ref.warning);
  run.settings = spec.settings(ref.image);
  DicSettings& s = run.settings;
  s.sequence.keep_frames = options.keep_frames;
  std::vector<dic::GridPoint> grid;
  try {
    grid =
        dic::make_grid(s.roi, ref.image.width, ref.image.height, s.sequence.dic.icgn.subset_size, s.sequence.dic.step);
  } catch (const InputError& e) {
    spec.rethrow(e);
  }

  // Issue 14: every frame is decoded and its size checked before any correlation, so that a bad file
  // at position 22 is found in seconds rather than after 21 frames of work. Each is dropped at once
  // (issue 16: memory stays bounded); decoding twice costs far less than correlating.
  const int n = static_cast<int>(images.size()) - 1;
  auto tick = std::chrono::steady_clock::now();
  for (int k = 1; k <= n; ++k) {
    log.reporter().report({"checking images", static_cast<std::size_t>(k), static_cast<std::size_t>(n), ""});
    image::require_same_size(ref.image, image::load_image(images[k]).image, images[k]);
  }
  run.stages.check = lap(tick);

  // A checkpoint a killed run left (--resume).
  const std::string print = fingerprint(spec, images, grid.size());
  const fs::path checkpoint_path = staged / kCheckpointName;
  std::optional<RunCheckpoint> resumed;
  if (options.resume) {
    std::error_code ec;
    if (fs::exists(checkpoint_path, ec)) {
      resumed = decode(io::read_text(checkpoint_path));
      if (!resumed || resumed->sizes.size() != 4)
        throw InputError({checkpoint_path.string(), 0, "--resume"}, "the checkpoint is unreadable", {},
                         "the one a killed `tricot dic` run left; run without --resume to start again");
      if (resumed->fingerprint != print)
        throw InputError({out_dir.string(), 0, "--resume"},
                         "the killed run in this folder used other images or settings", {},
                         "the same config, flags and images as the killed run, or no --resume to start again");
    } else {
      log.print("nothing to resume in " + out_dir.string() + "; starting from frame 0");
    }
  }

  std::unique_ptr<dic::SequenceTracker> tracker;
  int first = 1;
  if (resumed) {
    const dic::SequenceResumePoint at = dic::SequenceTracker::resume_point(resumed->tracker);
    if (at.next_frame > n + 1)
      throw InputError({checkpoint_path.string(), 0, "--resume"}, "the checkpoint is past the last image",
                       std::to_string(at.next_frame), "at most " + std::to_string(n + 1));
    first = at.next_frame;
    const image::Image r = at.reference_frame == 0 ? ref.image : image::load_image(images[at.reference_frame]).image;
    const image::Image prev =
        at.next_frame - 1 == at.reference_frame ? image::Image{} : image::load_image(images[at.next_frame - 1]).image;
    tracker = std::make_unique<dic::SequenceTracker>(r, prev, grid, s.sequence, resumed->tracker, log.reporter());
    run.lost_at = resumed->lost_at;
    log.print(fmt::format("resuming from frame {} (frames 0 to {} were complete)", first, first - 1));
  } else {
    tracker = std::make_unique<dic::SequenceTracker>(ref.image, grid, s.sequence, log.reporter());
  }
  run.resumed_from = first;

  const auto size_of = [&](int i) -> std::uint64_t { return resumed ? resumed->sizes[i] : 0; };
  const int vsg =
      dic::virtual_strain_gauge(s.sequence.dic.icgn.subset_size, s.sequence.dic.step, s.sequence.strain.window);
  GrowingFile points(staged / "points.csv", kPointsColumns, size_of(0));
  GrowingFile frames(staged / "frames.csv", kFramesColumns, size_of(1));
  std::optional<GrowingFile> increments, specimen;
  if (s.outputs.increments) increments.emplace(staged / "increments.csv", kIncrementsColumns, size_of(2));
  if (s.outputs.physical) specimen.emplace(staged / "specimen.csv", kSpecimenColumns, size_of(3));

  DicStageSeconds& st = run.stages;
  const auto write_frame = [&](const image::Image& img, const dic::TrackedFrame& f) {
    st.prepare += f.stages.prepare, st.correlate += f.stages.correlate, st.strain += f.stages.strain;
    st.increments += f.stages.increments;
    auto t = std::chrono::steady_clock::now();
    if (f.ok == 0 && run.lost_at < 0) run.lost_at = f.frame;
    std::string rows = points_rows(grid, f);
    if (const char* v = std::getenv("TRICOT_TEST_KILL_DIC_FRAME"); v && std::atoi(v) == f.frame) {
      points.append(rows.substr(0, rows.size() / 2));  // testing aid: a torn frame, then the kill
      points.flush();
      std::raise(SIGKILL);
    }
    points.append(rows);
    frames.append(frames_row(f, grid.size(), images[f.frame], vsg));
    if (increments && f.frame > 0) increments->append(increments_rows(grid, tracker->result().increments.back()));
    if (specimen) specimen->append(specimen_rows(grid, f, *s.outputs.physical));
    st.tables += lap(t);
    if (s.outputs.overlays && wanted(f.frame, s.outputs.overlay_every, n)) {
      io::write_atomic(staged / "overlays" / overlay_name(f.frame),
                       image::encode_png(dic::draw_overlay(img, grid, s.sequence.dic.step, f, s.outputs.overlay)));
      st.overlays += lap(t);
    }
    if (s.outputs.fields && wanted(f.frame, s.outputs.fields_every, n)) {
      io::write_vtu(staged / fields_name(f.frame), fields_vtu(grid, f, vsg));
      st.fields += lap(t);
    }
    // The frame is complete on disk: record where the tables end and the tracker's state (not after
    // the last frame: the run then publishes and there is nothing left to resume).
    if (f.frame == n) return;
    RunCheckpoint c;
    c.fingerprint = print;
    c.sizes = {points.flush(), frames.flush(), increments ? increments->flush() : 0, specimen ? specimen->flush() : 0};
    st.tables += lap(t);
    c.lost_at = run.lost_at;
    c.tracker = tracker->checkpoint();
    io::write_atomic(checkpoint_path, encode(c));
    st.checkpoint += lap(t);
  };

  if (!resumed) {
    const dic::TrackedFrame& f0 = tracker->result().frames.front();
    if (f0.ok == 0)
      throw InputError(
          {images[0], 0, ""}, "the reference image has no texture in the region of interest",
          fmt::format("{} subsets, all uniform", grid.size()),
          fmt::format("a gray-level spread above dic.min_texture = {} of full scale", s.sequence.dic.icgn.min_texture));
    write_frame(ref.image, f0);
  }
  log.reporter().report({"dic", static_cast<std::size_t>(first - 1), static_cast<std::size_t>(n), ""});
  for (int k = first; k <= n; ++k) {
    tick = std::chrono::steady_clock::now();
    const image::LoadedImage cur = image::load_image(images[k]);
    image::require_same_size(ref.image, cur.image, images[k]);
    st.decode += lap(tick);
    if (!cur.warning.empty()) warnings.push_back(cur.warning);
    const dic::TrackedFrame& f = tracker->add(cur.image);
    write_frame(cur.image, f);
    log.reporter().report({"dic", static_cast<std::size_t>(k), static_cast<std::size_t>(n),
                           fmt::format("frame {}: {}/{} ok, mean ZNCC {:.4f}", k, f.ok, grid.size(), f.mean_zncc)});
  }
  const dic::SequenceResult& r = tracker->result();

  points.close();
  frames.close();
  std::string written = (out_dir / "points.csv").string() + ", frames.csv";
  if (increments) increments->close(), written += ", increments.csv";
  if (specimen) specimen->close(), written += ", specimen.csv";
  if (s.outputs.fields) {
    std::vector<io::PvdEntry> entries;
    for (int k = 0; k <= n; ++k)
      if (wanted(k, s.outputs.fields_every, n)) entries.push_back({static_cast<double>(k), fields_name(k)});
    io::write_pvd(staged / "fields.pvd", entries);
    written += fmt::format(", fields.pvd ({} frames in {})", entries.size(), (out_dir / "fields").string());
  }
  if (s.outputs.overlays) {
    int count = 0;
    for (int k = 0; k <= n; ++k) count += wanted(k, s.outputs.overlay_every, n);
    written += fmt::format(", {} overlays in {}", count, (out_dir / "overlays").string());
  }
  {
    std::error_code ec;
    fs::remove(checkpoint_path, ec);  // the run is whole: nothing to resume
  }
  output.publish();
  run.frames = n + 1;
  log.print(fmt::format("{} ({} mode)", r.brief_report(), dic::to_string(s.sequence.mode)));
  log.print(fmt::format(
      "strains: virtual strain gauge {} px = ({} - 1) x {} px step + {} px subset ({}-point window; "
      "a sinusoidal strain keeps 90 % of its amplitude at periods >= {:.0f} px with first-order subsets)",
      vsg, s.sequence.strain.window, s.sequence.dic.step, s.sequence.dic.icgn.subset_size, s.sequence.strain.window,
      strain_p90(s.sequence.dic.icgn.subset_size, s.sequence.dic.step, s.sequence.strain.window)));
  log.print("wrote " + written);
  log.reporter().info("time per stage: " + st.brief_report());
  run.written = std::move(written);
  run.result = r;
  return run;
}

}  // namespace tricot::project
