// tricot dic [CONFIG.toml] [flags] -o DIR IMAGE...: digital image correlation over an image sequence
// (THEORY §10, DESIGN.md "dic"). The first image is the reference; images are read one at a time, so a
// long sequence never sits in memory. Writes DIR/points.csv (DESIGN.md columns), DIR/frames.csv, one
// overlay per frame, and on request DIR/increments.csv and DIR/specimen.csv.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "console.hpp"
#include "dic_config.hpp"
#include "tricot/dic/overlay.hpp"
#include "tricot/io/files.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

namespace fs = std::filesystem;

struct DicArgs {
  std::vector<std::string> inputs;  ///< [CONFIG.toml] IMAGE...
  std::string out_dir;
  int subset = 0, step = 0;
  std::string mode, roi;
  bool verbose = false, quiet = false;
};

constexpr const char* kFooter = R"(
The first IMAGE is the reference (frame 0); give the others in time order (8- or 16-bit TIFF, PNG,
BMP; colour is converted to gray with a warning). A square subset of --subset px sits on every grid
point (--step px apart) inside the region of interest; inverse-compositional Gauss-Newton (ZNSSD,
bicubic B-splines) matches it in every image, starting from FFT cross-correlation at a seed and
spreading to the neighbours with the highest correlation first.

Modes: incremental (default) correlates each image with the previous one and follows the material
points, which survives strains above 100 %; reference correlates every image with the first; auto
keeps the reference until the correlation drops, then moves it to the previous image.

Writes:
  DIR/points.csv    frame,id,x0,y0,x,y,u,v,zncc,status,exx,eyy,exy: one row per point and frame.
                    px, x to the right and y down; (x0, y0) in the reference, (x, y) in the frame;
                    status `ok` or why not (no_texture, low_correlation, out_of_image, lost, ...);
                    Green-Lagrange strains. Cells without a value are empty.
  DIR/frames.csv    frame, image, reference frame, points ok, mean ZNCC, seconds.
  DIR/overlays/frame_NNNN.png   displacement, strain and ZNCC maps drawn over each image.
  DIR/increments.csv            with [output] increments = true: fixed-point incremental fields.
  DIR/specimen.csv              with [physical] mm_per_px > 0: the same in specimen mm.

Examples:
  tricot dic -o out/dic frames/img_*.tif
  tricot dic --subset 41 --step 20 --roi 200,100,1800,900 -o out/dic ref.tif def1.tif def2.tif
  tricot dic --print-config > dic.toml     # every key, commented; edit, then:
  tricot dic dic.toml --mode auto -o out/dic frames/*.png

Exit codes: 0 ok, 2 bad command line or config, 3 an image or the config is missing or unreadable
(or an image's size differs from the reference), 4 every point was lost (results are still written).
)";

bool is_config(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".toml";
}

/// A number for a CSV cell: empty when there is none.
std::string cell(double v, const char* format = "{:.5f}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string();
}

std::string points_csv(const dic::SequenceResult& r) {
  std::string s = "frame,id,x0,y0,x,y,u,v,zncc,status,exx,eyy,exy\n";
  s.reserve(s.size() + r.frames.size() * r.grid.size() * 110);
  for (const dic::TrackedFrame& f : r.frames)
    for (std::size_t k = 0; k < r.grid.size(); ++k) {
      const Vec2 X = r.grid[k].x, x = f.x[k];
      const bool ok = f.status[k] == dic::PointStatus::ok;
      const Vec2 u = ok ? Vec2(x - X) : Vec2::Constant(std::nan(""));
      const dic::StrainPoint& e = f.strain[k];
      fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{},{},{},{},{},{},{}\n", f.frame, k, cell(X(0)),
                     cell(X(1)), cell(ok ? x(0) : NAN), cell(ok ? x(1) : NAN), cell(u(0)), cell(u(1)),
                     cell(ok ? f.zncc[k] : NAN, "{:.6f}"), dic::to_string(f.status[k]),
                     cell(e.valid ? e.exx : NAN, "{:.7g}"), cell(e.valid ? e.eyy : NAN, "{:.7g}"),
                     cell(e.valid ? e.exy : NAN, "{:.7g}"));
    }
  return s;
}

std::string csv_word(const std::string& w) {
  if (w.find_first_of(",\"\n") == std::string::npos) return w;
  std::string q = "\"";
  for (char c : w) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string frames_csv(const dic::SequenceResult& r, const std::vector<std::string>& images) {
  std::string s = "frame,image,reference_frame,ok,points,mean_zncc,seconds\n";
  for (const dic::TrackedFrame& f : r.frames)
    s += fmt::format("{},{},{},{},{},{:.6f},{:.3f}\n", f.frame, csv_word(images[f.frame]), f.reference_frame, f.ok,
                     r.grid.size(), f.mean_zncc, f.seconds);
  return s;
}

std::string increments_csv(const dic::SequenceResult& r) {
  std::string s = "from,to,id,x,y,u,v,zncc,status\n";
  for (const dic::IncrementField& inc : r.increments)
    for (std::size_t k = 0; k < r.grid.size(); ++k) {
      const bool ok = inc.status[k] == dic::PointStatus::ok;
      fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{},{},{}\n", inc.from, inc.to, k, cell(r.grid[k].x(0)),
                     cell(r.grid[k].x(1)), cell(inc.u[k](0)), cell(inc.u[k](1)), cell(ok ? inc.zncc[k] : NAN, "{:.6f}"),
                     dic::to_string(inc.status[k]));
    }
  return s;
}

std::string specimen_csv(const dic::SequenceResult& r, const dic::PhysicalFrame& p) {
  std::string s = "frame,id,X0,Y0,X,Y,UX,UY,EXX,EYY,EXY,status\n";
  for (const dic::TrackedFrame& f : r.frames)
    for (std::size_t k = 0; k < r.grid.size(); ++k) {
      const bool ok = f.status[k] == dic::PointStatus::ok;
      const Vec2 X0 = p.point(r.grid[k].x);
      const Vec2 X = ok ? p.point(f.x[k]) : Vec2::Constant(NAN);
      const Vec2 U = ok ? p.vector(f.x[k] - r.grid[k].x) : Vec2::Constant(NAN);
      const dic::StrainPoint& e = f.strain[k];
      Mat2 E = Mat2::Constant(NAN);
      if (e.valid) E = p.tensor((Mat2() << e.exx, e.exy, e.exy, e.eyy).finished());
      fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{},{},{},{},{},{}\n", f.frame, k, cell(X0(0), "{:.6f}"),
                     cell(X0(1), "{:.6f}"), cell(X(0), "{:.6f}"), cell(X(1), "{:.6f}"), cell(U(0), "{:.6f}"),
                     cell(U(1), "{:.6f}"), cell(E(0, 0), "{:.7g}"), cell(E(1, 1), "{:.7g}"), cell(E(0, 1), "{:.7g}"),
                     dic::to_string(f.status[k]));
    }
  return s;
}

std::string overlay_name(int frame) { return fmt::format("frame_{:04d}.png", frame); }

ExitCode run_dic(const DicArgs& a) {
  std::string config;
  std::vector<std::string> images;
  for (std::size_t i = 0; i < a.inputs.size(); ++i) {
    if (i == 0 && is_config(a.inputs[i])) config = a.inputs[i];
    else images.push_back(a.inputs[i]);
  }
  if (images.empty())
    throw InputError({"command line", 0, "IMAGE"}, "no image given", {}, "the reference image, then the frames");

  // The config, then the flags over it.
  io::Node root = config.empty() ? io::default_config(dic_schema()) : io::read_config(dic_schema(), config);
  io::Node& d = root.section("dic");
  FlagKeys flags;
  if (a.subset) d.set("subset_size", std::int64_t{a.subset}), flags["dic.subset_size"] = "--subset";
  if (a.step) d.set("step", std::int64_t{a.step}), flags["dic.step"] = "--step";
  if (!a.mode.empty()) d.set("mode", a.mode), flags["dic.mode"] = "--mode";
  if (!a.roi.empty()) {
    d.set("roi", parse_roi_flag(a.roi));
    d.set("roi_polygon", io::Reals{});
    d.set("roi_mask", std::string());
    flags["dic.roi"] = "--roi";
  }

  // Every image must exist before any work starts.
  for (const auto& img : images) {
    std::error_code ec;
    if (!fs::exists(img, ec)) throw FileError({img, 0, ""}, "image not found");
  }
  const fs::path out_dir = a.out_dir;
  {
    std::error_code ec;
    if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec))
      throw FileError({a.out_dir, 0, ""}, "output folder is a file");
  }

  std::vector<std::string> warnings;
  const image::LoadedImage ref = image::load_image(images[0]);
  if (!ref.warning.empty()) warnings.push_back(ref.warning);
  const DicSettings s =
      build_dic_settings(root, ref.image, config.empty() ? fs::path() : fs::path(config).parent_path(), flags);
  std::vector<dic::GridPoint> grid;
  try {
    grid = dic::make_grid(s.roi, ref.image.width, ref.image.height, s.sequence.dic.icgn.subset_size, s.sequence.dic.step);
  } catch (const InputError& e) {
    rethrow_in_config(root, e, flags);
  }

  Console console(a.verbose, a.quiet);
  dic::SequenceTracker tracker(ref.image, grid, s.sequence, console.reporter());
  const auto write_overlay = [&](const image::Image& img, const dic::TrackedFrame& f) {
    if (s.outputs.overlays)
      io::write_atomic(out_dir / "overlays" / overlay_name(f.frame),
                       image::encode_png(dic::draw_overlay(img, grid, s.sequence.dic.step, f, s.outputs.overlay)));
  };
  {
    const dic::TrackedFrame& f0 = tracker.result().frames.front();
    if (f0.ok == 0)
      throw InputError({images[0], 0, ""}, "the reference image has no texture in the region of interest",
                       fmt::format("{} subsets, all uniform", grid.size()),
                       fmt::format("a gray-level spread above dic.min_texture = {} of full scale",
                                   s.sequence.dic.icgn.min_texture));
    write_overlay(ref.image, f0);
  }
  const std::size_t n = images.size() - 1;
  console.reporter().report({"dic", 0, n, ""});
  for (std::size_t k = 1; k <= n; ++k) {
    const image::LoadedImage cur = image::load_image(images[k]);
    image::require_same_size(ref.image, cur.image, images[k]);
    if (!cur.warning.empty()) warnings.push_back(cur.warning);
    const dic::TrackedFrame& f = tracker.add(cur.image);
    write_overlay(cur.image, f);
    console.reporter().report({"dic", k, n,
                               fmt::format("frame {}: {}/{} ok, mean ZNCC {:.4f}", k, f.ok, grid.size(), f.mean_zncc)});
  }
  const dic::SequenceResult& r = tracker.result();

  io::write_atomic(out_dir / "points.csv", points_csv(r));
  io::write_atomic(out_dir / "frames.csv", frames_csv(r, images));
  std::string written = (out_dir / "points.csv").string() + ", frames.csv";
  if (s.outputs.increments) io::write_atomic(out_dir / "increments.csv", increments_csv(r)), written += ", increments.csv";
  if (s.outputs.physical) io::write_atomic(out_dir / "specimen.csv", specimen_csv(r, *s.outputs.physical)), written += ", specimen.csv";
  if (s.outputs.overlays) {
    io::remove_numbered_files(out_dir / "overlays", "frame_", ".png", static_cast<long>(r.frames.size()));
    written += fmt::format(", {} overlays in {}", r.frames.size(), (out_dir / "overlays").string());
  }
  const dic::TrackedFrame& last = r.frames.back();
  console.print(fmt::format("{} frames, {} points, {} mode: {}/{} ok in the last frame, mean ZNCC {:.4f}, {}",
                            r.frames.size(), grid.size(), dic::to_string(s.sequence.mode), last.ok, grid.size(),
                            last.mean_zncc, format_duration(r.seconds)));
  console.print("wrote " + written);
  if (!warnings.empty())
    std::fprintf(stderr, "tricot: warning: %s%s\n", warnings.front().c_str(),
                 warnings.size() > 1 ? fmt::format(" (and {} more images)", warnings.size() - 1).c_str() : "");
  if (r.termination == dic::SequenceTermination::all_lost) {
    int lost_at = 0;
    for (const auto& f : r.frames)
      if (f.ok == 0) {
        lost_at = f.frame;
        break;
      }
    std::fprintf(stderr, "tricot: error: %s: every point was lost (no point ok from frame %d on; see frames.csv)\n",
                 images[lost_at].c_str(), lost_at);
    return ExitCode::not_converged;
  }
  return ExitCode::ok;
}

}  // namespace

Runner add_dic(CLI::App& app) {
  auto args = std::make_shared<DicArgs>();
  CLI::App* cmd = app.add_subcommand("dic", "Digital image correlation over an image sequence (first image = reference)");
  cmd->footer(kFooter);
  cmd->add_option("inputs", args->inputs, "[CONFIG.toml] IMAGE...: an optional config (see --print-config), then the images")
      ->required();
  cmd->add_option("-o,--out", args->out_dir, "Output folder")->required();
  cmd->add_option("--subset", args->subset, "Subset size in px, odd (overrides dic.subset_size; default 31)")
      ->check(CLI::Range(7, 301));
  cmd->add_option("--step", args->step, "Grid step in px (overrides dic.step; default 10)")->check(CLI::Range(1, 1000));
  cmd->add_option("--mode", args->mode, "incremental, reference or auto (overrides dic.mode; default incremental)")
      ->check(CLI::IsMember({"incremental", "reference", "auto"}));
  cmd->add_option("--roi", args->roi, "Region of interest X0,Y0,X1,Y1 in px (overrides dic.roi; default the whole image)");
  cmd->add_flag("-v,--verbose", args->verbose, "Log every frame (points ok, mean ZNCC, seeds, reference updates)");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress line");
  add_print_config(cmd, dic_schema);
  return [args]() { return run_dic(*args); };
}

}  // namespace tricot::cli
