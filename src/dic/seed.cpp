// FFT cross-correlation seeds (see seed.hpp).
#include "tricot/dic/seed.hpp"

#include <algorithm>
#include <cmath>
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

}  // namespace tricot::dic
