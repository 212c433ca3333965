// The config of `tricot dic`: its schema, its spec and the engine settings built from it (dic_spec.hpp).
#include "tricot/project/dic_spec.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "spec/schema.hpp"
#include "tricot/image/image.hpp"

namespace tricot::project {

namespace {

const Strings kPanels = {"displacement", "u", "v", "exx", "eyy", "exy", "zncc"};

}  // namespace

io::SectionSpec dic_schema() {
  const DicTable d0;
  const StrainTable s0;
  const PhysicalTable p0;
  const OutputTable o0;
  SectionSpec root{"",
                   "tricot dic: digital image correlation over an image sequence (docs/theory.md §10).\n"
                   "The first image is the reference. Positions are in px, x to the right and y down.\n"
                   "Every key may be left out; flags (--subset, --step, --mode, --roi) override the file.",
                   false,
                   {},
                   {}};
  SectionSpec d{"dic", "Subsets, grid, correlation and sequence mode.", false, {}, {}};
  d.keys = {
      key("subset_size", std::int64_t{d0.subset_size},
          "Subset size N: N×N px, odd. Larger is less noisy, smaller follows sharper gradients.", 7, 301),
      key("step", std::int64_t{d0.step}, "Grid step in px between subset centres.", 1, 1000),
      key("mode", d0.mode,
          "incremental: each image against the previous one (survives > 100 % strain; positions accumulate).\n"
          "reference: every image against the first. auto: keep the reference until the correlation drops,\n"
          "then move it to the previous image (Ncorr's step analysis).",
          -kInf, kInf, {"incremental", "reference", "auto"}),
      key("order", d0.order,
          "Shape function: first (affine) or second order; auto (the default): second order only where an F-test\n"
          "on the residual says it pays (steep gradients), first order elsewhere (less noise).",
          -kInf, kInf, {"first", "second", "auto"}),
      key("roi", Reals{}, "Region of interest: [x0, y0, x1, y1] px, a rectangle; [] = the whole image."),
      key("roi_polygon", Reals{},
          "Region of interest as a polygon: [x0, y0, x1, y1, x2, y2, ...] px (at least 3 vertices)."),
      key("roi_mask", std::string(""),
          "Region of interest as a mask image (same size as the reference; white = inside), relative to this file."),
      key("seeds", Reals{},
          "Seed points [x0, y0, x1, y1, ...] px in the reference image; [] = the point nearest the ROI centre."),
      key("search_radius", std::int64_t{d0.search_radius}, "px: how far the FFT cross-correlation seed search looks.",
          1, 10000),
      key("max_seeds", std::int64_t{d0.max_seeds}, "Seed attempts per image pair before unreached points are given up.",
          1, 1000),
      key("seed_min_zncc", d0.seed_min_zncc,
          "A seed must correlate at least this well (the points it spreads to need min_zncc).", 0, 1),
      key("max_iterations", std::int64_t{d0.max_iterations}, "IC-GN iterations per subset.", 1, 1000),
      key("tolerance", d0.tolerance, "px: IC-GN stops when the update moves the subset by less than this.", 1e-9, 1),
      key("min_zncc", d0.min_zncc, "A point whose ZNCC is below this is `low_correlation` (not ok).", 0, 1),
      key("min_texture", d0.min_texture,
          "Fraction of full scale: a subset whose gray-level spread is below it is `no_texture`.", 0, 0.99),
      key("prefilter_sigma", d0.prefilter_sigma,
          "px: Gaussian pre-filter of every image (0 = none; 0.5–1 lowers the noise-induced bias).", 0, 5),
      key("weight_sigma", d0.weight_sigma,
          "px: Gaussian weighting window of each subset, exp(-r²/2σ²) (0 = uniform weights). N/4–N/6 keeps the\n"
          "noise of a smaller subset's neighbour but follows steep gradients better (see docs/validation.md).",
          0, 1000),
      key("update_zncc", d0.update_zncc, "auto mode: update the reference when a frame's mean ZNCC drops below this.",
          0, 1),
      key("update_loss", d0.update_loss, "auto mode: ... or when more than this fraction of the points fail.", 0, 1),
      key("batch", std::int64_t{d0.batch}, "Points propagated per round (1 = strict highest-ZNCC-first order).", 1,
          4096),
      key("threads", std::int64_t{d0.threads},
          "OpenMP threads, 0 = all cores; more than the cores run as many as the cores.", 0, 1024),
  };
  SectionSpec st{
      "strain", "Green–Lagrange strain by a least-squares plane fit over a window of grid points.", false, {}, {}};
  st.keys = {
      key("window", std::int64_t{s0.window}, "Grid points per side of the fitting window, odd.", 3, 51),
      key("min_fraction", s0.min_fraction, "The fit needs this fraction of the window's points to be ok.", 0, 1),
  };
  SectionSpec ph{"physical",
                 "Specimen coordinates (mm) for identification: the camera aims at the specimen centre, which\n"
                 "stays at a fixed pixel. With mm_per_px > 0, DIR/specimen.csv repeats points.csv in mm.",
                 false,
                 {},
                 {}};
  ph.keys = {
      key("mm_per_px", p0.mm_per_px, "Pixel size in mm; 0 = no specimen.csv.", 0, 1e6),
      key("centre_px", Reals{}, "[x, y] px: the specimen centre in the images; [] = the image centre."),
      key("angle_deg", p0.angle_deg, "Specimen X axis, counter-clockwise on screen from the image x axis, degrees.",
          -360, 360),
      key("y_up", p0.y_up, "The specimen Y axis points up on screen (image y points down)."),
  };
  SectionSpec out{"output", "What is written besides DIR/points.csv and DIR/frames.csv.", false, {}, {}};
  out.keys = {
      key("overlays", o0.overlays, "DIR/overlays/frame_NNNN.png: maps drawn over the images (see overlay_every)."),
      key("overlay_every", std::int64_t{o0.overlay_every},
          "An overlay of frame 0, of every n-th frame and of the last (1 = every frame; drawing costs time).", 1,
          1000000),
      key("panels", o0.panels, "Maps in each overlay, two per row: displacement, u, v, exx, eyy, exy, zncc."),
      key("panel_width", std::int64_t{o0.panel_width}, "px: each map is scaled down to at most this width.", 100,
          10000),
      key("zncc_floor", o0.zncc_floor, "The ZNCC map's colours span [zncc_floor, 1].", 0, 0.999),
      key("increments", o0.increments,
          "DIR/increments.csv: displacement between consecutive images at the fixed grid centres\n"
          "(the paper's WIMA-style incremental fields; costs a second correlation per image)."),
      key("fields", o0.fields,
          "DIR/fields/frame_NNNN.vtu (compressed binary: u, v, strains, ZNCC, status on the reference grid)\n"
          "and DIR/fields.pvd, the series ParaView opens (see fields_every)."),
      key("fields_every", std::int64_t{o0.fields_every},
          "Fields of frame 0, of every n-th frame and of the last (1 = every frame).", 1, 1000000),
  };
  root.sections = {d, st, ph, out};
  return root;
}

io::Reals parse_roi_flag(const std::string& text) {
  Reals r;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    const std::string cell = text.substr(pos, comma - pos);
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(v))
      throw InputError(Location{"command line", 0, "--roi"}, "not four numbers", "\"" + text + "\"",
                       "X0,Y0,X1,Y1 in px");
    r.push_back(v);
    pos = comma + 1;
  }
  if (r.size() != 4)
    throw InputError(Location{"command line", 0, "--roi"}, "not four numbers", "\"" + text + "\"", "X0,Y0,X1,Y1 in px");
  return r;
}

DicSpec DicSpec::from_config(const io::Node& root, std::filesystem::path dir) {
  DicSpec x;
  x.dir = std::move(dir);
  const Node& d = root.section("dic");
  DicTable& t = x.dic;
  t.origin = Origin(d);
  t.subset_size = static_cast<int>(d.integer("subset_size"));
  t.step = static_cast<int>(d.integer("step"));
  t.mode = d.string("mode");
  t.order = d.string("order");
  t.roi = d.reals("roi");
  t.roi_polygon = d.reals("roi_polygon");
  t.roi_mask = d.string("roi_mask");
  t.seeds = d.reals("seeds");
  t.search_radius = static_cast<int>(d.integer("search_radius"));
  t.max_seeds = static_cast<int>(d.integer("max_seeds"));
  t.seed_min_zncc = d.real("seed_min_zncc");
  t.max_iterations = static_cast<int>(d.integer("max_iterations"));
  t.tolerance = d.real("tolerance");
  t.min_zncc = d.real("min_zncc");
  t.min_texture = d.real("min_texture");
  t.prefilter_sigma = d.real("prefilter_sigma");
  t.weight_sigma = d.real("weight_sigma");
  t.update_zncc = d.real("update_zncc");
  t.update_loss = d.real("update_loss");
  t.batch = static_cast<int>(d.integer("batch"));
  t.threads = static_cast<int>(d.integer("threads"));
  const Node& st = root.section("strain");
  x.strain = {static_cast<int>(st.integer("window")), st.real("min_fraction"), Origin(st)};
  const Node& ph = root.section("physical");
  x.physical = {ph.real("mm_per_px"), ph.reals("centre_px"), ph.real("angle_deg"), ph.boolean("y_up"), Origin(ph)};
  const Node& out = root.section("output");
  OutputTable& o = x.output;
  o.overlays = out.boolean("overlays");
  o.overlay_every = static_cast<int>(out.integer("overlay_every"));
  o.panels = out.strings("panels");
  o.panel_width = static_cast<int>(out.integer("panel_width"));
  o.zncc_floor = out.real("zncc_floor");
  o.increments = out.boolean("increments");
  o.fields = out.boolean("fields");
  o.fields_every = static_cast<int>(out.integer("fields_every"));
  o.origin = Origin(out);
  return x;
}

void DicSpec::rethrow(const InputError& e) const {
  for (const Origin* o : {&dic.origin, &strain.origin, &physical.origin, &output.origin})
    if (o->owns(e)) o->rethrow(e);
  throw;
}

DicSettings DicSpec::settings(const image::Image& reference) const {
  DicSettings s;
  const Origin& d = dic.origin;
  try {
    // [dic]
    dic::IcgnOptions& icgn = s.sequence.dic.icgn;
    icgn.subset_size = dic.subset_size;
    icgn.order = dic.order == "second" ? dic::ShapeOrder::second
                 : dic.order == "auto" ? dic::ShapeOrder::automatic
                                       : dic::ShapeOrder::first;
    icgn.max_iterations = dic.max_iterations;
    icgn.tolerance = dic.tolerance;
    icgn.min_zncc = dic.min_zncc;
    icgn.min_texture = dic.min_texture;
    icgn.weight_sigma = dic.weight_sigma;
    dic::DicOptions& o = s.sequence.dic;
    o.step = dic.step;
    o.search_radius = dic.search_radius;
    o.max_seeds = dic.max_seeds;
    o.seed_min_zncc = dic.seed_min_zncc;
    o.prefilter_sigma = dic.prefilter_sigma;
    o.batch = dic.batch;
    o.threads = dic.threads;
    const Reals& seeds = dic.seeds;
    if (seeds.size() % 2 != 0)
      d.fail("seeds", "needs pairs of coordinates", std::to_string(seeds.size()) + " numbers", "[x0, y0, x1, y1, ...]");
    // Issue 14: a point outside the reference image is an error, never silently dropped or clipped.
    const double W = reference.width - 1.0, H = reference.height - 1.0;
    const auto inside = [&](double x, double y) { return x >= 0 && x <= W && y >= 0 && y <= H; };
    const std::string image_range = fmt::format("within the {}x{} reference image: 0 <= x <= {}, 0 <= y <= {}",
                                                reference.width, reference.height, W, H);
    for (std::size_t i = 0; i + 1 < seeds.size(); i += 2) {
      if (!inside(seeds[i], seeds[i + 1]))
        d.fail("seeds", fmt::format("seed {} lies outside the image", i / 2 + 1),
               fmt::format("({}, {})", seeds[i], seeds[i + 1]), image_range);
      o.seeds.emplace_back(seeds[i], seeds[i + 1]);
    }
    s.sequence.mode = dic.mode == "reference" ? dic::SequenceMode::reference
                      : dic.mode == "auto"    ? dic::SequenceMode::automatic
                                              : dic::SequenceMode::incremental;
    s.sequence.update_zncc = dic.update_zncc;
    s.sequence.update_loss = dic.update_loss;

    // The region of interest: one of roi, roi_polygon, roi_mask.
    const Reals& rect = dic.roi;
    const Reals& poly = dic.roi_polygon;
    const std::string& mask = dic.roi_mask;
    const int kinds = !rect.empty() + !poly.empty() + !mask.empty();
    if (kinds > 1) d.fail("roi", "give only one of roi, roi_polygon and roi_mask");
    if (!rect.empty()) {
      if (rect.size() != 4)
        d.fail("roi", "needs four numbers", std::to_string(rect.size()) + " numbers", "[x0, y0, x1, y1]");
      const std::string got = fmt::format("[{}, {}, {}, {}]", rect[0], rect[1], rect[2], rect[3]);
      if (!(rect[0] < rect[2] && rect[1] < rect[3]))
        d.fail("roi", "inverted or empty rectangle", got, "x0 < x1 and y0 < y1");
      if (!inside(rect[0], rect[1]) || !inside(rect[2], rect[3]))
        d.fail("roi", "the rectangle reaches outside the image", got, image_range);
      s.roi = dic::Roi::rectangle(rect[0], rect[1], rect[2], rect[3]);
    } else if (!poly.empty()) {
      if (poly.size() < 6 || poly.size() % 2 != 0)
        d.fail("roi_polygon", "needs at least 3 vertices", std::to_string(poly.size()) + " numbers",
               "[x0, y0, x1, y1, x2, y2, ...]");
      std::vector<Vec2> v;
      for (std::size_t i = 0; i + 1 < poly.size(); i += 2) {
        if (!inside(poly[i], poly[i + 1]))
          d.fail("roi_polygon", fmt::format("vertex {} lies outside the image", i / 2 + 1),
                 fmt::format("({}, {})", poly[i], poly[i + 1]), image_range);
        v.emplace_back(poly[i], poly[i + 1]);
      }
      s.roi = dic::Roi::from_polygon(std::move(v));
    } else if (!mask.empty()) {
      std::filesystem::path p = mask;
      if (p.is_relative()) p = dir / p;
      image::Image m = image::load_image(p).image;
      if (m.width != reference.width || m.height != reference.height)
        d.fail("roi_mask", "mask image size differs from the reference image",
               std::to_string(m.width) + "x" + std::to_string(m.height),
               std::to_string(reference.width) + "x" + std::to_string(reference.height));
      s.roi = dic::Roi::from_mask(std::move(m));
    }

    // [strain]
    s.sequence.strain.window = strain.window;
    s.sequence.strain.min_fraction = strain.min_fraction;

    // [physical]
    if (physical.mm_per_px > 0) {
      dic::PhysicalFrame pf;
      pf.mm_per_px = physical.mm_per_px;
      const Reals& c = physical.centre_px;
      if (!c.empty() && c.size() != 2)
        physical.origin.fail("centre_px", "needs two numbers", std::to_string(c.size()) + " numbers", "[x, y]");
      pf.centre_px = c.empty() ? Vec2(0.5 * (reference.width - 1), 0.5 * (reference.height - 1)) : Vec2(c[0], c[1]);
      pf.angle_deg = physical.angle_deg;
      pf.y_up = physical.y_up;
      pf.validate();
      s.outputs.physical = pf;
    }

    // [output]
    s.outputs.overlays = output.overlays;
    if (output.overlay_every < 1)
      output.origin.fail("overlay_every", "out of range", std::to_string(output.overlay_every), "1 to 1000000");
    s.outputs.overlay_every = output.overlay_every;
    s.outputs.overlay.panels.clear();
    for (const std::string& name : output.panels) {
      const auto it = std::find(kPanels.begin(), kPanels.end(), name);
      if (it == kPanels.end()) {
        const std::string hint = io::closest_name(name, kPanels);
        output.origin.fail("panels", "unknown map" + (hint.empty() ? std::string() : "; did you mean '" + hint + "'?"),
                           "\"" + name + "\"", "displacement, u, v, exx, eyy, exy or zncc");
      }
      s.outputs.overlay.panels.push_back(static_cast<dic::OverlayField>(it - kPanels.begin()));
    }
    s.outputs.overlay.panel_width = output.panel_width;
    s.outputs.overlay.zncc_floor = output.zncc_floor;
    s.outputs.increments = output.increments;
    s.outputs.fields = output.fields;
    if (output.fields_every < 1)
      output.origin.fail("fields_every", "out of range", std::to_string(output.fields_every), "1 to 1000000");
    s.outputs.fields_every = output.fields_every;
    s.sequence.fixed_point_fields = s.outputs.increments;

    s.sequence.validate();  // every range of [dic] and [strain], named by their keys
    s.outputs.overlay.validate();
  } catch (const FileError&) {
    throw;  // a mask that cannot be read: already names its file
  } catch (const InputError& e) {
    rethrow(e);
  }
  return s;
}

}  // namespace tricot::project
