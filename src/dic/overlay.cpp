// Overlay pictures of a DIC frame (see overlay.hpp). OpenCV (private to this engine) draws the cells,
// the colour map (turbo) and the labels.
#include "tricot/dic/overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "tricot/core/error.hpp"

namespace tricot::dic {

const char* to_string(OverlayField f) {
  switch (f) {
    case OverlayField::displacement: return "|u| (px)";
    case OverlayField::u: return "u (px)";
    case OverlayField::v: return "v (px)";
    case OverlayField::exx: return "exx";
    case OverlayField::eyy: return "eyy";
    case OverlayField::exy: return "exy";
    case OverlayField::zncc: return "ZNCC";
  }
  return "?";
}

void OverlayOptions::validate() const {
  auto bad = [](const char* key, const std::string& got, const char* expected) {
    throw InputError(Location{"", 0, key}, "out of range", got, expected);
  };
  if (panels.empty()) bad("output.panels", "none", "at least one panel");
  check_ranges(*this);
  if (!(opacity >= 0 && opacity <= 1)) bad("output.opacity", std::to_string(opacity), "0 to 1");
}

namespace {

const double nan = std::numeric_limits<double>::quiet_NaN();

/// The value a panel shows at point k (NaN where there is none).
double value(OverlayField field, const std::vector<GridPoint>& grid, const TrackedFrame& f, std::size_t k) {
  if (f.status[k] != PointStatus::ok) return nan;
  const Vec2 u = f.x[k] - grid[k].x;
  const StrainPoint& s = f.strain[k];
  switch (field) {
    case OverlayField::displacement: return u.norm();
    case OverlayField::u: return u(0);
    case OverlayField::v: return u(1);
    case OverlayField::exx: return s.valid ? s.exx : nan;
    case OverlayField::eyy: return s.valid ? s.eyy : nan;
    case OverlayField::exy: return s.valid ? s.exy : nan;
    case OverlayField::zncc: return f.zncc[k];
  }
  return nan;
}

/// The 256 colours of OpenCV's turbo map (BGR).
const std::vector<cv::Vec3b>& turbo() {
  static const std::vector<cv::Vec3b> lut = [] {
    cv::Mat ramp(256, 1, CV_8U), colours;
    for (int i = 0; i < 256; ++i) ramp.at<std::uint8_t>(i) = static_cast<std::uint8_t>(i);
    cv::applyColorMap(ramp, colours, cv::COLORMAP_TURBO);
    std::vector<cv::Vec3b> v(256);
    for (int i = 0; i < 256; ++i) v[i] = colours.at<cv::Vec3b>(i);
    return v;
  }();
  return lut;
}

cv::Scalar colour(double t) {
  const cv::Vec3b c = turbo()[static_cast<int>(std::lround(std::clamp(t, 0.0, 1.0) * 255))];
  return cv::Scalar(c[0], c[1], c[2]);
}

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

/// One panel: the scaled image, the coloured cells, and a strip below with the title and colour bar.
cv::Mat panel(const cv::Mat& base, double scale, OverlayField field, const std::vector<GridPoint>& grid, int step,
              const TrackedFrame& f, const OverlayOptions& o) {
  std::vector<double> values(grid.size());
  std::vector<double> finite;
  for (std::size_t k = 0; k < grid.size(); ++k)
    if (std::isfinite(values[k] = value(field, grid, f, k))) finite.push_back(values[k]);
  double lo = o.zncc_floor, hi = 1.0;
  if (field != OverlayField::zncc && !finite.empty()) {
    std::sort(finite.begin(), finite.end());
    lo = finite[finite.size() * 2 / 100];
    hi = finite[finite.size() - 1 - finite.size() * 2 / 100];
    // a uniform field (frame 0's displacement, round-off strains): centre it in the colour range
    const double tiny = 1e-9 * std::max({1.0, std::abs(lo), std::abs(hi)});
    if (hi - lo < tiny) {
      const double mid = std::abs(0.5 * (lo + hi)) < tiny ? 0.0 : 0.5 * (lo + hi);
      const double pad = std::max(1e-6, 0.01 * std::abs(mid));
      lo = mid - pad, hi = mid + pad;
    }
  }
  cv::Mat layer = base.clone(), mask = cv::Mat::zeros(base.size(), CV_8U);
  constexpr int shift = 4;  // sub-pixel bits of the polygon corners
  const double h = 0.5 * step;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const bool marked = f.frame == 0 && f.status[k] != PointStatus::ok;
    if (!std::isfinite(values[k]) && !marked) continue;
    const Vec2 x = marked ? grid[k].x : f.x[k];
    const Mat2 F = f.strain[k].valid ? f.strain[k].F : Mat2::Identity();
    cv::Point corners[4];
    const double sx[4] = {-h, h, h, -h}, sy[4] = {-h, -h, h, h};
    for (int c = 0; c < 4; ++c) {
      const Vec2 p = (x + F * Vec2(sx[c], sy[c])) * scale * (1 << shift);
      corners[c] = cv::Point(static_cast<int>(std::lround(p(0))), static_cast<int>(std::lround(p(1))));
    }
    const cv::Scalar c = marked ? cv::Scalar(128, 128, 128) : colour((values[k] - lo) / (hi - lo));
    cv::fillConvexPoly(layer, corners, 4, c, cv::LINE_8, shift);
    cv::fillConvexPoly(mask, corners, 4, cv::Scalar(255), cv::LINE_8, shift);
  }
  cv::Mat mixed, out = base.clone();
  cv::addWeighted(base, 1 - o.opacity, layer, o.opacity, 0, mixed);
  mixed.copyTo(out, mask);
  // The strip: "frame k  |u| (px)", then the colour bar between its two end values.
  const int strip = 34;
  cv::Mat framed(out.rows + strip, out.cols, CV_8UC3, cv::Scalar(32, 32, 32));
  out.copyTo(framed(cv::Rect(0, 0, out.cols, out.rows)));
  const int font = cv::FONT_HERSHEY_SIMPLEX, baseline_y = out.rows + 23;
  const cv::Scalar white(235, 235, 235);
  const std::string title = "frame " + std::to_string(f.frame) + "  " + to_string(field);
  int bl = 0;
  const int title_w = cv::getTextSize(title, font, 0.55, 1, &bl).width;
  cv::putText(framed, title, cv::Point(8, baseline_y), font, 0.55, white, 1, cv::LINE_AA);
  if (finite.empty() && field != OverlayField::zncc) {
    const std::string none = "no values";
    const int w = cv::getTextSize(none, font, 0.5, 1, &bl).width;
    cv::putText(framed, none, cv::Point(out.cols - w - 10, baseline_y), font, 0.5, white, 1, cv::LINE_AA);
    return framed;
  }
  // the colour bar between its two end values, right-aligned, as wide as the title leaves room for
  const std::string lo_text = number(lo), hi_text = number(hi);
  const int hi_w = cv::getTextSize(hi_text, font, 0.5, 1, &bl).width,
            lo_w = cv::getTextSize(lo_text, font, 0.5, 1, &bl).width;
  const int bar_x1 = out.cols - hi_w - 16;
  const int bar_w = std::min(240, bar_x1 - (8 + title_w + 16 + lo_w + 6));
  if (bar_w >= 30) {
    const int bar_x0 = bar_x1 - bar_w;
    for (int i = 0; i < bar_w; ++i)
      cv::line(framed, cv::Point(bar_x0 + i, out.rows + 9), cv::Point(bar_x0 + i, out.rows + 25),
               colour(double(i) / (bar_w - 1)));
    cv::putText(framed, lo_text, cv::Point(bar_x0 - lo_w - 6, baseline_y), font, 0.5, white, 1, cv::LINE_AA);
    cv::putText(framed, hi_text, cv::Point(bar_x1 + 6, baseline_y), font, 0.5, white, 1, cv::LINE_AA);
  }
  return framed;
}

}  // namespace

image::RgbImage draw_overlay(const image::Image& current, const std::vector<GridPoint>& grid, int step,
                             const TrackedFrame& f, const OverlayOptions& o) {
  o.validate();
  const image::RgbImage gray = image::to_rgb(current);
  const cv::Mat rgb(gray.height, gray.width, CV_8UC3, const_cast<std::uint8_t*>(gray.rgb.data()));
  cv::Mat base;
  cv::cvtColor(rgb, base, cv::COLOR_RGB2BGR);
  const double scale = std::min(1.0, double(o.panel_width) / std::max(1, current.width));
  if (scale < 1) cv::resize(base, base, cv::Size(), scale, scale, cv::INTER_AREA);
  std::vector<cv::Mat> panels;
  for (OverlayField field : o.panels) panels.push_back(panel(base, scale, field, grid, step, f, o));
  const int columns = panels.size() > 1 ? 2 : 1, rows = static_cast<int>((panels.size() + 1) / 2);
  const int pw = panels[0].cols, ph = panels[0].rows, gap = 4;
  cv::Mat sheet(rows * ph + (rows - 1) * gap, columns * pw + (columns - 1) * gap, CV_8UC3, cv::Scalar(0, 0, 0));
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const int r = static_cast<int>(i) / 2, c = static_cast<int>(i) % 2;
    panels[i].copyTo(sheet(cv::Rect(c * (pw + gap), r * (ph + gap), pw, ph)));
  }
  cv::cvtColor(sheet, sheet, cv::COLOR_BGR2RGB);
  image::RgbImage out(sheet.cols, sheet.rows);
  for (int y = 0; y < sheet.rows; ++y)
    std::copy_n(sheet.ptr<std::uint8_t>(y), 3 * sheet.cols, &out.rgb[3 * std::size_t(y) * sheet.cols]);
  return out;
}

}  // namespace tricot::dic
