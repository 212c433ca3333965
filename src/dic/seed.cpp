// FFT cross-correlation seeds (see seed.hpp).
#include "tricot/dic/seed.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace tricot::dic {

IntegerMatch integer_search(const image::Image& ref, const image::Image& cur, const Vec2& centre, int N,
                            const Vec2& predicted, int R) {
  IntegerMatch out;
  const int M = N / 2;
  const int cx = static_cast<int>(std::lround(centre(0))), cy = static_cast<int>(std::lround(centre(1)));
  if (cx - M < 0 || cy - M < 0 || cx + M >= ref.width || cy + M >= ref.height) return out;
  const int px = static_cast<int>(std::lround(predicted(0))), py = static_cast<int>(std::lround(predicted(1)));
  // Window in the current image holding every candidate subset position.
  const int x0 = std::max(0, cx + px - R - M), y0 = std::max(0, cy + py - R - M);
  const int x1 = std::min(cur.width - 1, cx + px + R + M), y1 = std::min(cur.height - 1, cy + py + R + M);
  if (x1 - x0 + 1 < N || y1 - y0 + 1 < N) return out;
  const cv::Mat T(N, N, CV_32F, const_cast<float*>(ref.row(cy - M) + (cx - M)), sizeof(float) * ref.width);
  const cv::Mat S(y1 - y0 + 1, x1 - x0 + 1, CV_32F, const_cast<float*>(cur.row(y0) + x0), sizeof(float) * cur.width);
  cv::Scalar mean, stddev;
  cv::meanStdDev(T, mean, stddev);
  if (!(stddev[0] > 1e-6 * std::max(1.0, ref.full_scale))) return out;
  cv::Mat C;
  cv::matchTemplate(S, T, C, cv::TM_CCOEFF_NORMED);
  double best = -2;
  cv::Point at;
  for (int y = 0; y < C.rows; ++y)
    for (int x = 0; x < C.cols; ++x) {
      const float v = C.at<float>(y, x);
      if (std::isfinite(v) && v > best) best = v, at = cv::Point(x, y);
    }
  if (best <= -1.5) return out;
  out.displacement = Vec2(x0 + at.x + M - cx, y0 + at.y + M - cy);
  out.zncc = best;
  out.found = true;
  return out;
}

SeedGuess seed_guess(const Frame& ref, const Frame& cur, const Vec2& centre, int N, int R, const Vec2& predicted) {
  SeedGuess out;
  const IntegerMatch m = integer_search(ref.image, cur.image, centre, N, predicted, R);
  if (!m.found) return out;
  out.found = true;
  out.zncc = m.zncc;
  out.p = translation(m.displacement(0), m.displacement(1));
  // Satellites one subset away: their search only has to absorb the strain over that distance.
  const double d = N;
  const int r = static_cast<int>(std::ceil(0.6 * d)) + 2;  // up to 60 % strain between seed and satellite
  Vec2 plus[2], minus[2];
  bool has_plus[2], has_minus[2];
  for (int a = 0; a < 2; ++a) {
    const Vec2 e = a == 0 ? Vec2(d, 0) : Vec2(0, d);
    const IntegerMatch p = integer_search(ref.image, cur.image, centre + e, N, m.displacement, r);
    const IntegerMatch q = integer_search(ref.image, cur.image, centre - e, N, m.displacement, r);
    has_plus[a] = p.found && p.zncc > 0.3, has_minus[a] = q.found && q.zncc > 0.3;
    plus[a] = p.displacement, minus[a] = q.displacement;
  }
  for (int a = 0; a < 2; ++a) {
    Vec2 g = Vec2::Zero();
    if (has_plus[a] && has_minus[a]) g = (plus[a] - minus[a]) / (2 * d);
    else if (has_plus[a]) g = (plus[a] - m.displacement) / d;
    else if (has_minus[a]) g = (m.displacement - minus[a]) / d;
    // column a of ∇u: ∂u/∂x_a, ∂v/∂x_a
    out.p(1 + a) = g(0);
    out.p(7 + a) = g(1);
  }
  return out;
}

namespace {

/// The reference seen through x = c + F (X − c): an n×n template around c, sampled from the B-spline
/// (clamped to the image, so a template reaching past the border repeats the edge).
cv::Mat stretched_template(const Frame& ref, const Vec2& c, const Mat2& F, int n) {
  const int m = n / 2;
  const Mat2 Finv = F.inverse();
  const double W1 = ref.spline.width() - 1, H1 = ref.spline.height() - 1;
  cv::Mat T(n, n, CV_32F);
  for (int y = -m; y <= m; ++y)
    for (int x = -m; x <= m; ++x) {
      const Vec2 X = c + Finv * Vec2(x, y);
      T.at<float>(y + m, x + m) = ref.spline.value(std::clamp(X(0), 0.0, W1), std::clamp(X(1), 0.0, H1));
    }
  return T;
}

/// The rotation by `deg` degrees (counter-clockwise on screen is clockwise in image rows: the sign
/// only has to cover both turns).
Mat2 rotation(double deg) {
  const double t = deg * std::numbers::pi / 180;
  Mat2 R;
  R << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  return R;
}

struct Candidate {
  double zncc = -2;
  cv::Point at;  ///< top-left corner of the best match
  Mat2 F = Mat2::Identity();
};

/// Best match of `T` in `S` (ZNCC), within `roi` of S (whole S when empty).
void match(const cv::Mat& S, const cv::Mat& T, const Mat2& F, Candidate& best, cv::Rect roi = {}) {
  const cv::Mat window = roi.area() > 0 ? S(roi) : S;
  if (window.cols < T.cols || window.rows < T.rows) return;
  cv::Mat C;
  cv::matchTemplate(window, T, C, cv::TM_CCOEFF_NORMED);
  double mx = -2;
  cv::Point at;
  cv::minMaxLoc(C, nullptr, &mx, nullptr, &at);
  if (std::isfinite(mx) && mx > best.zncc) best = {mx, at + roi.tl(), F};
}

}  // namespace

SeedGuess wide_seed_guess(const Frame& ref, const Frame& cur, const Vec2& centre, int N) {
  SeedGuess out;
  const int n = 2 * N - 1;  // odd
  const cv::Mat S(cur.image.height, cur.image.width, CV_32F, const_cast<float*>(cur.image.pixels.data()));
  if (S.cols < n || S.rows < n) return out;
  cv::Scalar mean, stddev;
  cv::meanStdDev(S, mean, stddev);
  if (!(stddev[0] > 1e-6 * std::max(1.0, cur.image.full_scale))) return out;  // a blank image
  // 1. Locate: every candidate stretch, and rotations of near-isotropic ones (a free edge turns as
  // the knit shrinks), over the whole image at half resolution.
  cv::Mat S2;
  cv::resize(S, S2, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  std::vector<Mat2> coarse_F;
  const double stretches[] = {0.8, 1.0, 1.25, 1.55, 1.9};
  for (double sx : stretches)
    for (double sy : stretches) coarse_F.push_back(Vec2(sx, sy).asDiagonal());
  for (double deg : {-40.0, -25.0, -12.0, 12.0, 25.0, 40.0})
    for (double s : {0.9, 1.15, 1.45}) coarse_F.push_back(s * rotation(deg));
  Candidate coarse;
  for (const Mat2& F : coarse_F) {
    cv::Mat T2;
    cv::resize(stretched_template(ref, centre, F, n), T2, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    match(S2, T2, F, coarse);
  }
  if (coarse.zncc <= -1.5) return out;
  // 2. Refine at full resolution: stretches within ±12 % and turns within ±6° of the best, ±6 px
  // around its place.
  const int half2 = (n / 2) / 2;  // the half-resolution template's half width (resize rounds n/2)
  const cv::Point guess_centre(2 * (coarse.at.x + half2), 2 * (coarse.at.y + half2));
  const int r = 6;
  const cv::Rect roi = cv::Rect(guess_centre.x - n / 2 - r, guess_centre.y - n / 2 - r, n + 2 * r, n + 2 * r) &
                       cv::Rect(0, 0, S.cols, S.rows);
  Candidate fine;
  for (double deg : {-6.0, 0.0, 6.0})
    for (double fx : {0.89, 0.94, 1.0, 1.06, 1.12})
      for (double fy : {0.89, 0.94, 1.0, 1.06, 1.12}) {
        const Mat2 F = (rotation(deg) * Vec2(fx, fy).asDiagonal() * coarse.F).eval();
        match(S, stretched_template(ref, centre, F, n), F, fine, roi);
      }
  if (fine.zncc <= -1.5) return out;
  out.found = true;
  out.zncc = fine.zncc;
  const Vec2 matched(fine.at.x + n / 2, fine.at.y + n / 2);
  const Mat2 grad = fine.F - Mat2::Identity();
  out.p = translation(matched(0) - centre(0), matched(1) - centre(1));
  out.p(1) = grad(0, 0), out.p(2) = grad(0, 1), out.p(7) = grad(1, 0), out.p(8) = grad(1, 1);
  return out;
}

}  // namespace tricot::dic
