// Accuracy of subset matching on synthetic speckle with analytic motion and 2 % Gaussian noise
// (issue 5, "Must show"): bias and random error over sub-pixel shifts 0–1 px, uniform strain up to 5 %
// and rotation in one step. Images are rendered from the continuous pattern (no bitmap is warped), so
// the only errors are the correlation's own. Prints the tables of docs/validation.md.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "tricot/dic/correlate.hpp"
#include "tricot/dic/grid.hpp"
#include "tricot/synth/speckle.hpp"

using namespace tricot;
using namespace tricot::dic;

namespace {

/// The bounds at 2 % noise with 31 px subsets.
constexpr double kBiasTol = 0.002;   ///< px, mean error
constexpr double kRandomTol = 0.01;  ///< px, standard deviation of the error
constexpr double kNoise = 0.02;      ///< Gaussian noise, fraction of full scale, in both images
constexpr double kPrefilter = 0.7;   ///< px: Gaussian pre-filter against the noise-induced interpolation bias
constexpr int kRealisations = 2;     ///< noise draws per bounded case (each a fresh pair of noisy images)
constexpr int kSize = 400;           ///< px, square images

/// A fine, full-contrast speckle (2 px blobs on black): what a DIC practitioner would paint.
synth::SpeckleOptions speckle() {
  synth::SpeckleOptions o;
  o.radius = 2.0;
  o.background = 0.0;
  o.contrast = 1.0;
  o.subsamples = 2;
  return o;
}

struct Stats {
  double bias_u = 0, sd_u = 0, bias_v = 0, sd_v = 0;
  double bias_grad = 0;  ///< mean error of the displacement gradient (max over its four entries)
  int n = 0;
  int second = 0;  ///< points matched to second order (order = auto)
};

/// Correlates the reference with the moved image at every grid point, over kRealisations noise draws,
/// and compares with the true displacement u(X) and gradient. `guess`: start IC-GN from the truth
/// rounded to whole pixels (IC-GN alone); otherwise the full pipeline (FFT-CC seed, propagation).
Stats measure(const synth::InverseMotion& motion, const std::function<Vec2(const Vec2&)>& u_true, const Mat2& grad_true,
              double prefilter, bool guess, unsigned seed, int realisations = kRealisations,
              ShapeOrder order = ShapeOrder::first) {
  const synth::SpecklePattern P(speckle(), -20, -20, kSize + 20, kSize + 20);
  const image::Image ref = synth::render(P, kSize, kSize, synth::no_motion);
  const image::Image cur = synth::render(P, kSize, kSize, motion);
  // keep the warped subsets inside the image for every motion tried
  const auto grid = make_grid(Roi::rectangle(40, 40, kSize - 41, kSize - 41), kSize, kSize, 31, 8);
  std::vector<Vec2> c;
  for (const auto& g : grid) c.push_back(g.x);
  const auto nb = grid_neighbours(grid);
  DicOptions o;
  o.prefilter_sigma = prefilter;
  o.icgn.order = order;
  std::vector<std::optional<Shape>> guesses;
  if (guess)
    for (const Vec2& x : c) {
      const Vec2 u = u_true(x);
      guesses.push_back(translation(std::round(u(0)), std::round(u(1))));
    }
  double su = 0, su2 = 0, sv = 0, sv2 = 0;
  Mat2 sg = Mat2::Zero();
  Stats s;
  for (int q = 0; q < realisations; ++q) {
    const Frame f = prepare_frame(synth::add_noise(ref, kNoise, seed + 2 * q), prefilter);
    const Frame g = prepare_frame(synth::add_noise(cur, kNoise, seed + 2 * q + 1), prefilter);
    const PairResult r = correlate_pair(f, g, c, nb, o, guesses);
    for (std::size_t k = 0; k < c.size(); ++k) {
      // a large rotation carries the corner subsets out of the image: the only acceptable failure
      if (r.points[k].status == PointStatus::out_of_image) continue;
      EXPECT_EQ(r.points[k].status, PointStatus::ok) << c[k].transpose() << " " << r.message;
      if (r.points[k].status != PointStatus::ok) continue;
      const Vec2 e = Vec2(r.points[k].p(0), r.points[k].p(6)) - u_true(c[k]);
      su += e(0), su2 += e(0) * e(0), sv += e(1), sv2 += e(1) * e(1);
      sg += displacement_gradient(r.points[k].p) - grad_true;
      ++s.n;
      s.second += r.points[k].p.segment<3>(3).squaredNorm() + r.points[k].p.segment<3>(9).squaredNorm() > 0;
    }
  }
  s.bias_u = su / s.n, s.bias_v = sv / s.n;
  s.sd_u = std::sqrt(std::max(0.0, su2 / s.n - s.bias_u * s.bias_u));
  s.sd_v = std::sqrt(std::max(0.0, sv2 / s.n - s.bias_v * s.bias_v));
  s.bias_grad = (sg / s.n).cwiseAbs().maxCoeff();
  return s;
}

void print(const char* label, const Stats& s) {
  std::printf("%-26s %+.5f  %.5f  %+.5f  %.5f  %.1e  %d\n", label, s.bias_u, s.sd_u, s.bias_v, s.sd_v, s.bias_grad,
              s.n);
}

void header(const char* title) {
  std::printf("\n%s\n%-26s %-8s  %-7s  %-8s  %-7s  %-7s  %s\n", title, "case", "bias_u", "sd_u", "bias_v", "sd_v",
              "|bias ∇u|", "points");
}

}  // namespace

TEST(IcgnNoise, BiasAndRandomErrorStayWithinBoundsOverSubPixelShiftsAtTwoPercentNoise) {
  // shift (s, s/2): u sweeps 0–1 px, v 0–0.5 px
  for (double prefilter : {kPrefilter, 0.0}) {
    char title[96];
    std::snprintf(title, sizeof title, "sub-pixel shifts, 2 %% noise, 31 px subsets, pre-filter %.1f px", prefilter);
    header(title);
    for (int i = 0; i <= 10; ++i) {
      const double u = 0.1 * i, v = 0.05 * i;
      // without the pre-filter: one noise draw, printed for comparison
      const Stats s =
          measure([&](const Vec2& x) { return Vec2(x(0) - u, x(1) - v); }, [&](const Vec2&) { return Vec2(u, v); },
                  Mat2::Zero(), prefilter, true, 100 + i, prefilter > 0 ? kRealisations : 1);
      char label[32];
      std::snprintf(label, sizeof label, "shift (%.2f, %.2f) px", u, v);
      print(label, s);
      EXPECT_LE(s.sd_u, kRandomTol) << label;
      EXPECT_LE(s.sd_v, kRandomTol) << label;
      if (prefilter > 0) {  // without the pre-filter the noise-induced bias is printed, not bounded
        EXPECT_LE(std::abs(s.bias_u), kBiasTol) << label;
        EXPECT_LE(std::abs(s.bias_v), kBiasTol) << label;
      }
    }
  }
}

TEST(IcgnNoise, TricotDicsDefaultOrderAutoKeepsTheBoundsOverSubPixelShiftsAndAStrain) {
  // Issue 16: `tricot dic` matches to second order only where the F-test (99.9 %) says it pays. On a
  // translation or a uniform strain nothing pays: a few points take second order by chance, and the bias
  // and random error stay within the bounds above. Without the pre-filter (tricot dic's default) and with
  // it (the F-test then counts the pre-filter's noise correlation, icgn.hpp).
  for (double prefilter : {0.0, kPrefilter}) {
    char title[128];
    std::snprintf(title, sizeof title,
                  "order = auto: shifts and a 5 %% / -2.5 %% strain, 2 %% noise, 31 px subsets, pre-filter %.1f px",
                  prefilter);
    header(title);
    int second = 0, n = 0;
    const int draws = prefilter > 0 ? kRealisations : 1;
    for (int i = 0; i <= 10; i += 2) {
      const double u = 0.1 * i, v = 0.05 * i;
      const Stats s =
          measure([&](const Vec2& x) { return Vec2(x(0) - u, x(1) - v); }, [&](const Vec2&) { return Vec2(u, v); },
                  Mat2::Zero(), prefilter, true, 100 + i, draws, ShapeOrder::automatic);
      char label[32];
      std::snprintf(label, sizeof label, "shift (%.2f, %.2f) px", u, v);
      print(label, s);
      EXPECT_LE(s.sd_u, kRandomTol) << label;
      EXPECT_LE(s.sd_v, kRandomTol) << label;
      if (prefilter > 0) {  // without the pre-filter the bias is printed, as for first order above
        EXPECT_LE(std::abs(s.bias_u), kBiasTol) << label;
        EXPECT_LE(std::abs(s.bias_v), kBiasTol) << label;
      }
      second += s.second, n += s.n;
    }
    const Vec2 c(kSize / 2.0, kSize / 2.0);
    const Mat2 G = (Mat2() << 0.05, 0, 0, -0.025).finished();
    const Stats s = measure([&](const Vec2& x) { return Vec2(c + (Mat2::Identity() + G).inverse() * (x - c)); },
                            [&](const Vec2& X) { return Vec2(G * (X - c)); }, G, prefilter, false, 300, draws,
                            ShapeOrder::automatic);
    print("strain 5 % / -2.5 %", s);
    EXPECT_LE(s.sd_u, kRandomTol);
    EXPECT_LE(s.sd_v, kRandomTol);
    EXPECT_LE(s.bias_grad, 1e-4);
    second += s.second, n += s.n;
    std::printf("second order at %d of %d points (%.2f %%)\n", second, n, 100.0 * second / n);
    EXPECT_LE(second, n / 50) << prefilter;  // a few by chance, never a systematic switch
  }
}

TEST(IcgnNoise, UniformStrainUpToFivePercentIsMeasuredInOneStep) {
  header("uniform strain in one step (full pipeline: FFT-CC seed, propagation), 2 % noise, pre-filter 0.7 px");
  const Vec2 c(kSize / 2.0, kSize / 2.0);
  for (double e : {0.01, 0.02, 0.05}) {
    // x = c + diag(1 + e, 1 − e/2)(X − c)
    const Mat2 grad = Vec2(e, -0.5 * e).asDiagonal();
    const Mat2 F_inv = (Mat2::Identity() + grad).inverse();
    const Stats s = measure([&](const Vec2& x) { return Vec2(c + F_inv * (x - c)); },
                            [&](const Vec2& X) { return Vec2(grad * (X - c)); }, grad, kPrefilter, false, 300);
    char label[32];
    std::snprintf(label, sizeof label, "strain %.0f %% / %.1f %%", 100 * e, -50 * e);
    print(label, s);
    EXPECT_LE(std::abs(s.bias_u), kBiasTol) << label;
    EXPECT_LE(std::abs(s.bias_v), kBiasTol) << label;
    EXPECT_LE(s.sd_u, kRandomTol) << label;
    EXPECT_LE(s.sd_v, kRandomTol) << label;
    EXPECT_LE(s.bias_grad, 1e-4) << label;  // 1e-4 = 100 µstrain
  }
}

TEST(IcgnNoise, RotationIsMeasuredInOneStep) {
  header("rigid rotation about the image centre in one step (full pipeline), 2 % noise, pre-filter 0.7 px");
  const Vec2 c(kSize / 2.0, kSize / 2.0);
  for (double deg : {1.0, 5.0, 10.0}) {
    const double t = deg * std::numbers::pi / 180;
    const Mat2 R = (Mat2() << std::cos(t), -std::sin(t), std::sin(t), std::cos(t)).finished();
    const Stats s =
        measure([&](const Vec2& x) { return Vec2(c + R.transpose() * (x - c)); },
                [&](const Vec2& X) { return Vec2(c + R * (X - c) - X); }, R - Mat2::Identity(), kPrefilter, false, 500);
    char label[32];
    std::snprintf(label, sizeof label, "rotation %.0f deg", deg);
    print(label, s);
    EXPECT_LE(std::abs(s.bias_u), kBiasTol) << label;
    EXPECT_LE(std::abs(s.bias_v), kBiasTol) << label;
    EXPECT_LE(s.sd_u, kRandomTol) << label;
    EXPECT_LE(s.sd_v, kRandomTol) << label;
    EXPECT_LE(s.bias_grad, 1e-4) << label;
  }
}
