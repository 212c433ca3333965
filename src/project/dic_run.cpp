// tricot dic's pipeline (see dic_run.hpp).
#include "tricot/project/dic_run.hpp"

#include "tricot/project/output_dir.hpp"

#include <fmt/format.h>

#include <cmath>

#include "tricot/dic/overlay.hpp"
#include "tricot/image/image.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

namespace {

/// A number for a CSV cell: empty when there is none.
std::string cell(double v, const char* format = "{:.5f}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string();
}

std::string csv_word(const std::string& w) {
  if (w.find_first_of(",\"\n") == std::string::npos) return w;
  std::string q = "\"";
  for (char c : w) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string overlay_name(int frame) { return fmt::format("frame_{:04d}.png", frame); }

}  // namespace

std::string points_csv(const dic::SequenceResult& r) {
  std::string s = "frame,id,x0,y0,x,y,u,v,zncc,status,exx,eyy,exy,sigma_x,sigma_y\n";
  s.reserve(s.size() + r.frames.size() * r.grid.size() * 110);
  for (const dic::TrackedFrame& f : r.frames)
    for (std::size_t k = 0; k < r.grid.size(); ++k) {
      const Vec2 X = r.grid[k].x, x = f.x[k];
      const bool ok = f.status[k] == dic::PointStatus::ok;
      const Vec2 u = ok ? Vec2(x - X) : Vec2::Constant(std::nan(""));
      const dic::StrainPoint& e = f.strain[k];
      const Vec2 sg = ok && k < f.sigma.size() ? f.sigma[k] : Vec2::Constant(std::nan(""));
      fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", f.frame, k, cell(X(0)),
                     cell(X(1)), cell(ok ? x(0) : NAN), cell(ok ? x(1) : NAN), cell(u(0)), cell(u(1)),
                     cell(ok ? f.zncc[k] : NAN, "{:.6f}"), dic::to_string(f.status[k]),
                     cell(e.valid ? e.exx : NAN, "{:.7g}"), cell(e.valid ? e.eyy : NAN, "{:.7g}"),
                     cell(e.valid ? e.exy : NAN, "{:.7g}"), cell(sg(0), "{:.4g}"), cell(sg(1), "{:.4g}"));
    }
  return s;
}

std::string frames_csv(const dic::SequenceResult& r, const std::vector<std::string>& images) {
  std::string s = "frame,image,reference_frame,ok,points,mean_zncc,seconds\n";
  for (const dic::TrackedFrame& f : r.frames)
    s += fmt::format("{},{},{},{},{},{:.6f},{:.3f}\n", f.frame, csv_word(images[f.frame]), f.reference_frame, f.ok,
                     r.grid.size(), f.mean_zncc, f.seconds);
  return s;
}

std::string increments_csv(const dic::SequenceResult& r) {
  std::string s = "from,to,id,x,y,u,v,zncc,status,sigma_x,sigma_y\n";
  for (const dic::IncrementField& inc : r.increments)
    for (std::size_t k = 0; k < r.grid.size(); ++k) {
      const bool ok = inc.status[k] == dic::PointStatus::ok;
      const Vec2 sg = ok && k < inc.sigma.size() ? inc.sigma[k] : Vec2::Constant(std::nan(""));
      fmt::format_to(std::back_inserter(s), "{},{},{},{},{},{},{},{},{},{},{}\n", inc.from, inc.to, k, cell(r.grid[k].x(0)),
                     cell(r.grid[k].x(1)), cell(inc.u[k](0)), cell(inc.u[k](1)), cell(ok ? inc.zncc[k] : NAN, "{:.6f}"),
                     dic::to_string(inc.status[k]), cell(sg(0), "{:.4g}"), cell(sg(1), "{:.4g}"));
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

DicSpec dic_spec(const std::string& file, const DicFlags& a) {
  const io::Node root = file.empty() ? io::default_config(dic_schema()) : io::read_config(dic_schema(), file);
  DicSpec spec = DicSpec::from_config(root, file.empty() ? fs::path() : fs::path(file).parent_path());
  DicTable& d = spec.dic;
  if (a.subset) d.subset_size = *a.subset, d.origin.set_by_flag("subset_size", "--subset");
  if (a.step) d.step = *a.step, d.origin.set_by_flag("step", "--step");
  if (!a.mode.empty()) d.mode = a.mode, d.origin.set_by_flag("mode", "--mode");
  if (!a.roi.empty()) {
    d.roi = parse_roi_flag(a.roi);
    d.roi_polygon.clear();
    d.roi_mask.clear();
    d.origin.set_by_flag("roi", "--roi");
  }
  return spec;
}

DicRun run_dic(const DicSpec& spec, const std::vector<std::string>& images, const fs::path& out_dir,
               const Log& log) {
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
  OutputDir output(out_dir, "dic");  // written in staging, published at the end (issue 14)
  const fs::path staged = output.staging();
  const image::LoadedImage ref = image::load_image(images[0]);
  if (!ref.warning.empty()) warnings.push_back(ref.warning);
  run.settings = spec.settings(ref.image);
  const DicSettings& s = run.settings;
  std::vector<dic::GridPoint> grid;
  try {
    grid = dic::make_grid(s.roi, ref.image.width, ref.image.height, s.sequence.dic.icgn.subset_size, s.sequence.dic.step);
  } catch (const InputError& e) {
    spec.rethrow(e);
  }

  // Issue 14: every frame is decoded and its size checked before any correlation, so that a bad file
  // at position 22 is found in seconds rather than after 21 frames of work. Decoding twice costs far
  // less than correlating.
  const std::size_t n = images.size() - 1;
  for (std::size_t k = 1; k <= n; ++k) {
    log.reporter().report({"checking images", k, n, ""});
    image::require_same_size(ref.image, image::load_image(images[k]).image, images[k]);
  }

  dic::SequenceTracker tracker(ref.image, grid, s.sequence, log.reporter());
  const auto write_overlay = [&](const image::Image& img, const dic::TrackedFrame& f) {
    if (s.outputs.overlays)
      io::write_atomic(staged / "overlays" / overlay_name(f.frame),
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
  log.reporter().report({"dic", 0, n, ""});
  for (std::size_t k = 1; k <= n; ++k) {
    const image::LoadedImage cur = image::load_image(images[k]);
    image::require_same_size(ref.image, cur.image, images[k]);
    if (!cur.warning.empty()) warnings.push_back(cur.warning);
    const dic::TrackedFrame& f = tracker.add(cur.image);
    write_overlay(cur.image, f);
    log.reporter().report({"dic", k, n,
                               fmt::format("frame {}: {}/{} ok, mean ZNCC {:.4f}", k, f.ok, grid.size(), f.mean_zncc)});
  }
  const dic::SequenceResult& r = tracker.result();

  io::write_atomic(staged / "points.csv", points_csv(r));
  io::write_atomic(staged / "frames.csv", frames_csv(r, images));
  std::string written = (out_dir / "points.csv").string() + ", frames.csv";
  if (s.outputs.increments) io::write_atomic(staged / "increments.csv", increments_csv(r)), written += ", increments.csv";
  if (s.outputs.physical) io::write_atomic(staged / "specimen.csv", specimen_csv(r, *s.outputs.physical)), written += ", specimen.csv";
  if (s.outputs.overlays) {
    written += fmt::format(", {} overlays in {}", r.frames.size(), (out_dir / "overlays").string());
  }
  output.publish();
  const dic::TrackedFrame& last = r.frames.back();
  log.print(fmt::format("{} frames, {} points, {} mode: {}/{} ok in the last frame, mean ZNCC {:.4f}, {}",
                            r.frames.size(), grid.size(), dic::to_string(s.sequence.mode), last.ok, grid.size(),
                            last.mean_zncc, format_duration(r.seconds)));
  log.print("wrote " + written);
  run.written = std::move(written);
  run.result = r;
  return run;
}

}  // namespace tricot::project
