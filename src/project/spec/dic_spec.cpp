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

dic::SequenceOptions DicSpec::verb_defaults() {
  dic::SequenceOptions o;
  o.dic.icgn.order = dic::ShapeOrder::automatic;
  return o;
}

io::SectionSpec dic_schema() {
  const DicSpec d0;
  SectionSpec root{"",
                   "tricot dic: digital image correlation over an image sequence (docs/theory.md §10).\n"
                   "The first image is the reference. Positions are in px, x to the right and y down.\n"
                   "Every key may be left out; flags (--subset, --step, --mode, --roi) override the file.",
                   false,
                   {},
                   {}};
  SectionSpec d{"dic", "Subsets, grid, correlation and sequence mode.", false, {}, {}};
  add_keys(d, d0.sequence.dic.icgn);
  add_keys(d, d0.sequence.dic);
  add_keys(d, d0.sequence);
  add_keys(d, d0.dic);
  SectionSpec st{
      "strain", "Green–Lagrange strain by a least-squares plane fit over a window of grid points.", false, {}, {}};
  add_keys(st, d0.sequence.strain);
  SectionSpec ph{"physical",
                 "Specimen coordinates (mm) for identification: the camera aims at the specimen centre, which\n"
                 "stays at a fixed pixel. With mm_per_px > 0, DIR/specimen.csv repeats points.csv in mm.",
                 false,
                 {},
                 {}};
  add_keys(ph, d0.physical);
  SectionSpec out{"output", "What is written besides DIR/points.csv and DIR/frames.csv.", false, {}, {}};
  add_keys(out, d0.output);
  add_keys(out, d0.overlay);
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
  read_keys(d, x.sequence.dic.icgn);
  read_keys(d, x.sequence.dic);
  read_keys(d, x.sequence);
  read_keys(d, x.dic);
  x.dic.origin = Origin(d);
  const Node& st = root.section("strain");
  read_keys(st, x.sequence.strain);
  x.strain = Origin(st);
  const Node& ph = root.section("physical");
  read_keys(ph, x.physical);
  x.physical.origin = Origin(ph);
  const Node& out = root.section("output");
  read_keys(out, x.output);
  read_keys(out, x.overlay);
  x.output.origin = Origin(out);
  return x;
}

void DicSpec::rethrow(const InputError& e) const {
  for (const Origin* o : {&dic.origin, &strain, &physical.origin, &output.origin})
    if (o->owns(e)) o->rethrow(e);
  throw;
}

DicSettings DicSpec::settings(const image::Image& reference) const {
  DicSettings s;
  const Origin& d = dic.origin;
  try {
    // [dic] and [strain]: the engine's own keys, as read
    s.sequence = sequence;
    dic::DicOptions& o = s.sequence.dic;
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

    // [physical]
    check_ranges(physical);  // the verb's own keys set in code (a file's were checked when read)
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
    check_ranges(output);  // the verb's own keys set in code (a file's were checked when read)
    s.outputs.overlays = output.overlays;
    s.outputs.overlay_every = output.overlay_every;
    s.outputs.overlay = overlay;
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
    s.outputs.increments = output.increments;
    s.outputs.fields = output.fields;
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
