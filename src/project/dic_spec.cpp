// The config of `tricot dic` and its builder (see dic_config.hpp).
#include "tricot/project/dic_spec.hpp"

#include <cmath>

#include "schema.hpp"
#include "tricot/image/image.hpp"

namespace tricot::project {

namespace {

const Strings kPanels = {"displacement", "u", "v", "exx", "eyy", "exy", "zncc"};

}  // namespace

io::SectionSpec dic_schema() {
  SectionSpec root{"",
                   "tricot dic: digital image correlation over an image sequence (THEORY §10).\n"
                   "The first image is the reference. Positions are in px, x to the right and y down.\n"
                   "Every key may be left out; flags (--subset, --step, --mode, --roi) override the file.",
                   false, {}, {}};
  SectionSpec d{"dic", "Subsets, grid, correlation and sequence mode.", false, {}, {}};
  d.keys = {
      key("subset_size", std::int64_t{31}, "Subset size N: N×N px, odd. Larger is less noisy, smaller follows sharper gradients.", 7, 301),
      key("step", std::int64_t{10}, "Grid step in px between subset centres.", 1, 1000),
      key("mode", std::string("incremental"),
          "incremental: each image against the previous one (survives > 100 % strain; positions accumulate).\n"
          "reference: every image against the first. auto: keep the reference until the correlation drops,\n"
          "then move it to the previous image (Ncorr's step analysis).",
          -kInf, kInf, {"incremental", "reference", "auto"}),
      key("order", std::string("first"), "Shape function: first (affine) or second order.", -kInf, kInf, {"first", "second"}),
      key("roi", Reals{}, "Region of interest: [x0, y0, x1, y1] px, a rectangle; [] = the whole image."),
      key("roi_polygon", Reals{}, "Region of interest as a polygon: [x0, y0, x1, y1, x2, y2, ...] px (at least 3 vertices)."),
      key("roi_mask", std::string(""), "Region of interest as a mask image (same size as the reference; white = inside), relative to this file."),
      key("seeds", Reals{}, "Seed points [x0, y0, x1, y1, ...] px in the reference image; [] = the point nearest the ROI centre."),
      key("search_radius", std::int64_t{50}, "px: how far the FFT cross-correlation seed search looks.", 1, 10000),
      key("max_seeds", std::int64_t{8}, "Seed attempts per image pair before unreached points are given up.", 1, 1000),
      key("seed_min_zncc", 0.9, "A seed must correlate at least this well (the points it spreads to need min_zncc).", 0, 1),
      key("max_iterations", std::int64_t{50}, "IC-GN iterations per subset.", 1, 1000),
      key("tolerance", 1e-3, "px: IC-GN stops when the update moves the subset by less than this.", 1e-9, 1),
      key("min_zncc", 0.7, "A point whose ZNCC is below this is `low_correlation` (not ok).", 0, 1),
      key("min_texture", 0.005, "Fraction of full scale: a subset whose gray-level spread is below it is `no_texture`.", 0, 0.99),
      key("prefilter_sigma", 0.0, "px: Gaussian pre-filter of every image (0 = none; 0.5–1 lowers the noise-induced bias).", 0, 5),
      key("update_zncc", 0.95, "auto mode: update the reference when a frame's mean ZNCC drops below this.", 0, 1),
      key("update_loss", 0.02, "auto mode: ... or when more than this fraction of the points fail.", 0, 1),
      key("batch", std::int64_t{32}, "Points propagated per round (1 = strict highest-ZNCC-first order).", 1, 4096),
      key("threads", std::int64_t{0}, "OpenMP threads, 0 = all cores.", 0, 1024),
  };
  SectionSpec st{"strain", "Green–Lagrange strain by a least-squares plane fit over a window of grid points.", false, {}, {}};
  st.keys = {
      key("window", std::int64_t{5}, "Grid points per side of the fitting window, odd.", 3, 51),
      key("min_fraction", 0.35, "The fit needs this fraction of the window's points to be ok.", 0, 1),
  };
  SectionSpec ph{"physical",
                 "Specimen coordinates (mm) for identification: the camera aims at the specimen centre, which\n"
                 "stays at a fixed pixel. With mm_per_px > 0, DIR/specimen.csv repeats points.csv in mm.",
                 false, {}, {}};
  ph.keys = {
      key("mm_per_px", 0.0, "Pixel size in mm; 0 = no specimen.csv.", 0, 1e6),
      key("centre_px", Reals{}, "[x, y] px: the specimen centre in the images; [] = the image centre."),
      key("angle_deg", 0.0, "Specimen X axis, counter-clockwise on screen from the image x axis, degrees.", -360, 360),
      key("y_up", true, "The specimen Y axis points up on screen (image y points down)."),
  };
  SectionSpec out{"output", "What is written besides DIR/points.csv and DIR/frames.csv.", false, {}, {}};
  out.keys = {
      key("overlays", true, "DIR/overlays/frame_NNNN.png: maps drawn over every image."),
      key("panels", Strings{"displacement", "exx", "eyy", "zncc"},
          "Maps in each overlay, two per row: displacement, u, v, exx, eyy, exy, zncc."),
      key("panel_width", std::int64_t{800}, "px: each map is scaled down to at most this width.", 100, 10000),
      key("zncc_floor", 0.9, "The ZNCC map's colours span [zncc_floor, 1].", 0, 0.999),
      key("increments", false,
          "DIR/increments.csv: displacement between consecutive images at the fixed grid centres\n"
          "(the paper's WIMA-style incremental fields; costs a second correlation per image)."),
  };
  root.sections = {d, st, ph, out};
  return root;
}

void rethrow_in_config(const io::Node& root, const InputError& e, const FlagKeys& flags) {
  if (!e.where().file.empty()) throw;
  const std::string dotted = e.where().key;
  if (auto it = flags.find(dotted); it != flags.end())
    throw InputError(Location{"command line", 0, it->second}, problem_of(e));
  const auto dot = dotted.find('.');
  const std::string section = dotted.substr(0, dot);
  for (const char* known : {"dic", "strain", "physical", "output"})
    if (dot != std::string::npos && section == known) {
      const Node& n = root.section(section);
      Location where = n.where(dotted.substr(dot + 1));
      where.key = dotted;
      throw InputError(where, problem_of(e));
    }
  throw;
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
      throw InputError(Location{"command line", 0, "--roi"}, "not four numbers", "\"" + text + "\"", "X0,Y0,X1,Y1 in px");
    r.push_back(v);
    pos = comma + 1;
  }
  if (r.size() != 4)
    throw InputError(Location{"command line", 0, "--roi"}, "not four numbers", "\"" + text + "\"", "X0,Y0,X1,Y1 in px");
  return r;
}

DicSettings build_dic_settings(const io::Node& root, const image::Image& reference,
                               const std::filesystem::path& config_dir, const FlagKeys& flags) {
  DicSettings s;
  const Node& d = root.section("dic");
  try {
    // [dic]
    dic::IcgnOptions& icgn = s.sequence.dic.icgn;
    icgn.subset_size = static_cast<int>(d.integer("subset_size"));
    if (icgn.subset_size % 2 == 0) {
      if (flags.count("dic.subset_size"))
        throw InputError(Location{"command line", 0, "--subset"}, "must be odd", std::to_string(icgn.subset_size),
                         "an odd number of px from 7 to 301");
      d.fail("subset_size", "must be odd", std::to_string(icgn.subset_size), "an odd number of px from 7 to 301");
    }
    icgn.order = d.string("order") == "second" ? dic::ShapeOrder::second : dic::ShapeOrder::first;
    icgn.max_iterations = static_cast<int>(d.integer("max_iterations"));
    icgn.tolerance = d.real("tolerance");
    icgn.min_zncc = d.real("min_zncc");
    icgn.min_texture = d.real("min_texture");
    dic::DicOptions& o = s.sequence.dic;
    o.step = static_cast<int>(d.integer("step"));
    o.search_radius = static_cast<int>(d.integer("search_radius"));
    o.max_seeds = static_cast<int>(d.integer("max_seeds"));
    o.seed_min_zncc = d.real("seed_min_zncc");
    o.prefilter_sigma = d.real("prefilter_sigma");
    o.batch = static_cast<int>(d.integer("batch"));
    o.threads = static_cast<int>(d.integer("threads"));
    const Reals& seeds = d.reals("seeds");
    if (seeds.size() % 2 != 0)
      d.fail("seeds", "needs pairs of coordinates", std::to_string(seeds.size()) + " numbers", "[x0, y0, x1, y1, ...]");
    for (std::size_t i = 0; i + 1 < seeds.size(); i += 2) o.seeds.emplace_back(seeds[i], seeds[i + 1]);
    const std::string& mode = d.string("mode");
    s.sequence.mode = mode == "reference" ? dic::SequenceMode::reference
                      : mode == "auto"    ? dic::SequenceMode::automatic
                                          : dic::SequenceMode::incremental;
    s.sequence.update_zncc = d.real("update_zncc");
    s.sequence.update_loss = d.real("update_loss");

    // The region of interest: one of roi, roi_polygon, roi_mask.
    const Reals& rect = d.reals("roi");
    const Reals& poly = d.reals("roi_polygon");
    const std::string& mask = d.string("roi_mask");
    const int kinds = !rect.empty() + !poly.empty() + !mask.empty();
    if (kinds > 1) d.fail("roi", "give only one of roi, roi_polygon and roi_mask");
    if (!rect.empty()) {
      if (rect.size() != 4) d.fail("roi", "needs four numbers", std::to_string(rect.size()) + " numbers", "[x0, y0, x1, y1]");
      s.roi = dic::Roi::rectangle(rect[0], rect[1], rect[2], rect[3]);
    } else if (!poly.empty()) {
      if (poly.size() < 6 || poly.size() % 2 != 0)
        d.fail("roi_polygon", "needs at least 3 vertices", std::to_string(poly.size()) + " numbers",
               "[x0, y0, x1, y1, x2, y2, ...]");
      std::vector<Vec2> v;
      for (std::size_t i = 0; i + 1 < poly.size(); i += 2) v.emplace_back(poly[i], poly[i + 1]);
      s.roi = dic::Roi::from_polygon(std::move(v));
    } else if (!mask.empty()) {
      std::filesystem::path p = mask;
      if (p.is_relative()) p = config_dir / p;
      image::Image m = image::load_image(p).image;
      if (m.width != reference.width || m.height != reference.height)
        d.fail("roi_mask", "mask image size differs from the reference image",
               std::to_string(m.width) + "x" + std::to_string(m.height),
               std::to_string(reference.width) + "x" + std::to_string(reference.height));
      s.roi = dic::Roi::from_mask(std::move(m));
    }

    // [strain]
    const Node& st = root.section("strain");
    s.sequence.strain.window = static_cast<int>(st.integer("window"));
    if (s.sequence.strain.window % 2 == 0)
      st.fail("window", "must be odd", std::to_string(s.sequence.strain.window), "an odd number from 3 to 51");
    s.sequence.strain.min_fraction = st.real("min_fraction");

    // [physical]
    const Node& ph = root.section("physical");
    if (ph.real("mm_per_px") > 0) {
      dic::PhysicalFrame pf;
      pf.mm_per_px = ph.real("mm_per_px");
      const Reals& c = ph.reals("centre_px");
      if (!c.empty() && c.size() != 2) ph.fail("centre_px", "needs two numbers", std::to_string(c.size()) + " numbers", "[x, y]");
      pf.centre_px = c.empty() ? Vec2(0.5 * (reference.width - 1), 0.5 * (reference.height - 1)) : Vec2(c[0], c[1]);
      pf.angle_deg = ph.real("angle_deg");
      pf.y_up = ph.boolean("y_up");
      pf.validate();
      s.outputs.physical = pf;
    }

    // [output]
    const Node& out = root.section("output");
    s.outputs.overlays = out.boolean("overlays");
    s.outputs.overlay.panels.clear();
    for (const std::string& name : out.strings("panels")) {
      const auto it = std::find(kPanels.begin(), kPanels.end(), name);
      if (it == kPanels.end()) {
        const std::string hint = io::closest_name(name, kPanels);
        out.fail("panels", "unknown map" + (hint.empty() ? std::string() : "; did you mean '" + hint + "'?"),
                 "\"" + name + "\"", "displacement, u, v, exx, eyy, exy or zncc");
      }
      s.outputs.overlay.panels.push_back(static_cast<dic::OverlayField>(it - kPanels.begin()));
    }
    s.outputs.overlay.panel_width = static_cast<int>(out.integer("panel_width"));
    s.outputs.overlay.zncc_floor = out.real("zncc_floor");
    s.outputs.increments = out.boolean("increments");
    s.sequence.fixed_point_fields = s.outputs.increments;

    s.sequence.validate();
    s.outputs.overlay.validate();
  } catch (const FileError&) {
    throw;  // a mask that cannot be read: already names its file
  } catch (const InputError& e) {
    rethrow_in_config(root, e, flags);
  }
  return s;
}

}  // namespace tricot::project
