// Real DIC benchmark images that nobody on this project made (../shared/data, see its README.md):
// DIC Challenge 1.0 Samples 14 and 15, the DIC Challenge 2.0 star pair, and OpenCorr's 45 % tension
// series. Each test asserts only what the data's README justifies, and prints what it measured
// (docs/validation.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "testing/paths.hpp"
#include "tricot/dic/correlate.hpp"
#include "tricot/dic/grid.hpp"
#include "tricot/dic/sequence.hpp"
#include "tricot/image/image.hpp"

using namespace tricot;
using namespace tricot::dic;
namespace fs = std::filesystem;

namespace {

constexpr int kStep = 20;  ///< px: every 20th pixel keeps the test short; the docs use 10

fs::path data(const std::string& folder) { return test::shared_data() / folder; }

#define REQUIRE_DATA(folder) \
  if (!fs::exists(data(folder))) GTEST_SKIP() << data(folder) << " is missing (../shared/data)"

/// One image pair over the whole-image grid (31 px subsets).
struct Pair {
  std::vector<Vec2> centres;
  PairResult r;
  double mean(const std::function<double(const PointMatch&, const Vec2&)>& f, int* count = nullptr) const {
    double s = 0;
    int n = 0;
    for (std::size_t k = 0; k < centres.size(); ++k)
      if (r.points[k].status == PointStatus::ok) s += f(r.points[k], centres[k]), ++n;
    if (count) *count = n;
    return n ? s / n : NAN;
  }
};

Pair correlate(const Frame& f, const fs::path& current, const DicOptions& o = {}) {
  const Frame g = prepare_frame(image::load_image(current).image, o.prefilter_sigma);
  const auto grid = make_grid(Roi::whole_image(), f.image.width, f.image.height, o.icgn.subset_size, kStep);
  Pair p;
  for (const auto& q : grid) p.centres.push_back(q.x);
  p.r = correlate_pair(f, g, p.centres, grid_neighbours(grid), o);
  return p;
}

/// Sample 15's command.csv: a row y (px), then v for K50, K100, K150, ..., K400 (no header).
std::vector<std::vector<double>> command_table() {
  std::ifstream in(data("dic-challenge-15") / "command.csv");
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> row;
    std::istringstream l(line);
    for (std::string cell; std::getline(l, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

/// The imposed v at row y of the deformed image (linear between the table's integer rows).
double imposed_v(const std::vector<std::vector<double>>& table, int column, double y) {
  const int i = std::clamp(static_cast<int>(std::floor(y)), 0, static_cast<int>(table.size()) - 2);
  const double t = std::clamp(y - i, 0.0, 1.0);
  return (1 - t) * table[i][column] + t * table[i + 1][column];
}

}  // namespace

TEST(Sample15, RmsErrorOfVAgainstTheImposedDisplacementIsBelowFiveHundredthsOfAPixelInEveryImage) {
  REQUIRE_DATA("dic-challenge-15");
  // 0.05 px: the measured 0.02–0.035 px (first-order 31 px subsets on a 2 px-wide transition of the
  // K50 profile, plus 2 % noise) with a margin; u is imposed zero, so its RMS is the noise floor.
  constexpr double kRmsVTol = 0.05, kRmsUTol = 0.02;
  const auto table = command_table();
  const Frame f = prepare_frame(image::load_image(data("dic-challenge-15") / "reference.tif").image);
  std::printf("image              points_ok  mean_zncc  rms_v_error_px  rms_u_px\n");
  for (const auto& [name, column] : std::vector<std::pair<std::string, int>>{
           {"p200_k50_n2.tif", 1}, {"p200_k100_n2.tif", 2}, {"p200_k200_n2.tif", 4}, {"p200_k400_n2.tif", 8}}) {
    const Pair p = correlate(f, data("dic-challenge-15") / name);
    int n = 0;
    // the table is indexed by the row in the deformed image: read it at y0 + v (data README)
    const double ms_v = p.mean(
        [&, col = column](const PointMatch& m, const Vec2& c) {
          const double e = m.p(6) - imposed_v(table, col, c(1) + m.p(6));
          return e * e;
        },
        &n);
    const double ms_u = p.mean([](const PointMatch& m, const Vec2&) { return m.p(0) * m.p(0); });
    std::printf("%-18s %5d/%zu  %.4f     %.4f          %.4f\n", name.c_str(), n, p.centres.size(), p.r.mean_zncc,
                std::sqrt(ms_v), std::sqrt(ms_u));
    EXPECT_GT(n, static_cast<int>(0.95 * p.centres.size())) << name << ": " << p.r.message;
    EXPECT_LT(std::sqrt(ms_v), kRmsVTol) << name;
    EXPECT_LT(std::sqrt(ms_u), kRmsUTol) << name;
  }
}

TEST(Sample15, SecondOrderWhereItPaysKeepsK50WithinTwoHundredthsOfAPixelAtStepTen) {
  REQUIRE_DATA("dic-challenge-15");
  // Issue 16's goal: RMS v error <= 0.02 px over all points of K50 at step 10 (31 px subsets), the
  // truth read at the deformed row. First order gives 0.030 (0.052 in the 300-600 px transition, where
  // v's slope jumps at three kinks); dic.order = "auto" (second order where the F-test says it pays)
  // measured 0.0178 (0.0277 in the transition, 0.0106 outside it, the first-order noise floor).
  // Bounds: the goal, and ~10 % above the measured transition and flat-zone figures.
  constexpr double kRmsAllTol = 0.020, kRmsTransitionTol = 0.030, kRmsFlatTol = 0.0115;
  const auto table = command_table();
  const Frame f = prepare_frame(image::load_image(data("dic-challenge-15") / "reference.tif").image);
  const Frame g = prepare_frame(image::load_image(data("dic-challenge-15") / "p200_k50_n2.tif").image);
  DicOptions o;
  o.icgn.order = ShapeOrder::automatic;
  const auto grid = make_grid(Roi::whole_image(), f.image.width, f.image.height, o.icgn.subset_size, 10);
  std::vector<Vec2> centres;
  for (const auto& q : grid) centres.push_back(q.x);
  const PairResult r = correlate_pair(f, g, centres, grid_neighbours(grid), o);
  double all = 0, transition = 0, flat = 0;
  int n = 0, nt = 0, second = 0;
  for (std::size_t k = 0; k < centres.size(); ++k) {
    const PointMatch& m = r.points[k];
    if (m.status != PointStatus::ok) continue;
    const double e = m.p(6) - imposed_v(table, 1, centres[k](1) + m.p(6));
    all += e * e, ++n;
    if (centres[k](1) >= 300 && centres[k](1) <= 600) transition += e * e, ++nt;
    else flat += e * e;
    second += m.p.segment<3>(9).squaredNorm() > 0;
  }
  const double rms = std::sqrt(all / n), rms_t = std::sqrt(transition / nt), rms_f = std::sqrt(flat / (n - nt));
  std::printf("K50, step 10, order auto: %d/%zu ok (%d second order), RMS v %.4f px, 300-600 px %.4f, outside %.4f\n",
              n, centres.size(), second, rms, rms_t, rms_f);
  EXPECT_GT(n, static_cast<int>(0.95 * centres.size())) << r.message;
  EXPECT_LT(rms, kRmsAllTol);
  EXPECT_LT(rms_t, kRmsTransitionTol);
  EXPECT_LT(rms_f, kRmsFlatTol);
}

TEST(Sample14, CorrelatesAtHighZnccWithNoVerticalMotionAndAStillLeftEdge) {
  REQUIRE_DATA("dic-challenge-14");
  // The README: u(x) is a 0.1 px sinusoid, v = 0, and x < 100 px does not move. The noise floor of
  // these images is ~0.013 px, so 0.03 px bounds both the RMS of v and the mean |u| at the left edge.
  constexpr double kStillTol = 0.03;
  const Frame f = prepare_frame(image::load_image(data("dic-challenge-14") / "sample14_reference.tif").image);
  std::printf("image              points_ok  mean_zncc  rms_v_px  mean|u|_x<100_px  max|u|_px\n");
  for (const char* name : {"sample14_l1.tif", "sample14_l3.tif", "sample14_l5.tif"}) {
    const Pair p = correlate(f, data("dic-challenge-14") / name);
    int n = 0, left = 0;
    const double ms_v = p.mean([](const PointMatch& m, const Vec2&) { return m.p(6) * m.p(6); }, &n);
    double still = 0, max_u = 0;
    for (std::size_t k = 0; k < p.centres.size(); ++k)
      if (p.r.points[k].status == PointStatus::ok) {
        max_u = std::max(max_u, std::abs(p.r.points[k].p(0)));
        if (p.centres[k](0) + 15 < 100) still += std::abs(p.r.points[k].p(0)), ++left;
      }
    std::printf("%-18s %5d/%zu  %.4f     %.4f    %.4f            %.4f\n", name, n, p.centres.size(), p.r.mean_zncc,
                std::sqrt(ms_v), still / left, max_u);
    EXPECT_GT(n, static_cast<int>(0.9 * p.centres.size())) << name << ": " << p.r.message;
    EXPECT_GT(p.r.mean_zncc, 0.98) << name;
    EXPECT_LT(std::sqrt(ms_v), kStillTol) << name;
    ASSERT_GT(left, 0);
    EXPECT_LT(still / left, kStillTol) << name;
  }
}

TEST(StarPair, CorrelatesAtHighZnccAndStaysWithinTheImposedAmplitude) {
  REQUIRE_DATA("dic-challenge-star");
  // The README: v is a sinusoid of 0.5 px amplitude, u = 0. A subset can only smooth the sinusoid,
  // so |v| stays below the amplitude plus the noise (0.05 px allows ~4 σ); u is noise only.
  constexpr double kAmplitude = 0.5, kNoiseMargin = 0.05, kRmsUTol = 0.03;
  const Frame f = prepare_frame(image::load_image(data("dic-challenge-star") / "star_reference_noisy.tif").image);
  const Pair p = correlate(f, data("dic-challenge-star") / "star_deformed_noisy.tif");
  int n = 0;
  const double ms_u = p.mean([](const PointMatch& m, const Vec2&) { return m.p(0) * m.p(0); }, &n);
  double max_v = 0;
  for (const auto& m : p.r.points)
    if (m.status == PointStatus::ok) max_v = std::max(max_v, std::abs(m.p(6)));
  std::printf("star pair: %d/%zu ok, mean ZNCC %.4f, max |v| %.4f px, RMS u %.4f px\n", n, p.centres.size(),
              p.r.mean_zncc, max_v, std::sqrt(ms_u));
  EXPECT_GT(n, static_cast<int>(0.9 * p.centres.size())) << p.r.message;
  EXPECT_GT(p.r.mean_zncc, 0.98);
  EXPECT_LT(max_v, kAmplitude + kNoiseMargin);
  EXPECT_LT(std::sqrt(ms_u), kRmsUTol);
}

TEST(TensionSeries, FortyFivePercentInOneStepAndThroughTheSeriesGivesTheNominalStretch) {
  REQUIRE_DATA("synthetic-tension");
  // The README: utn_NN is utn_00 stretched by NN % along x, so exx = ½(λ² − 1) with λ = 1 + NN/100.
  // The median over the strip is free of its ends; 1e-3 is 0.2 % of the 45 % strain.
  constexpr double kStrainTol = 1e-3;
  const int stretches[] = {30, 35, 40, 45};
  std::vector<image::Image> images{image::load_image(data("synthetic-tension") / "utn_00.png").image};
  for (int s : stretches)
    images.push_back(image::load_image(data("synthetic-tension") / ("utn_" + std::to_string(s) + ".png")).image);
  auto median_exx = [](const TrackedFrame& f) {
    std::vector<double> v;
    for (std::size_t k = 0; k < f.strain.size(); ++k)
      if (f.status[k] == PointStatus::ok && f.strain[k].valid) v.push_back(f.strain[k].exx);
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v.empty() ? NAN : v[v.size() / 2];
  };
  for (SequenceMode mode : {SequenceMode::reference, SequenceMode::incremental}) {
    SequenceOptions o;
    o.mode = mode;
    o.dic.step = kStep;
    // reference mode: one step from utn_00 to utn_45; incremental: through the whole series
    const std::vector<image::Image> seq =
        mode == SequenceMode::reference ? std::vector<image::Image>{images.front(), images.back()} : images;
    const SequenceResult r = track_sequence(seq, Roi::whole_image(), o);
    const TrackedFrame& last = r.frames.back();
    const double exx = median_exx(last), nominal = 0.5 * (1.45 * 1.45 - 1);
    std::printf(
        "%s mode, utn_00 -> utn_45 in %zu step(s): %d/%d ok (textured: %d), mean ZNCC %.4f, median exx %.5f "
        "(nominal %.5f)\n",
        to_string(mode), seq.size() - 1, last.ok, static_cast<int>(r.grid.size()), r.frames.front().ok, last.mean_zncc,
        exx, nominal);
    EXPECT_GT(last.ok, static_cast<int>(0.9 * r.frames.front().ok)) << last.message;
    EXPECT_GT(last.mean_zncc, 0.9);
    EXPECT_NEAR(exx, nominal, kStrainTol);
  }
}
