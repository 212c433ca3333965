// Correlating one image pair at many points: FFT-CC seeds, then reliability-guided propagation (the
// highest-ZNCC point hands its shape to its neighbours first, Pan 2009, doi:10.1364/AO.48.001535, as in
// Ncorr), IC-GN at every point, OpenMP over points (docs/theory.md §10).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "tricot/core/progress.hpp"
#include "tricot/dic/icgn.hpp"

namespace tricot::dic {

/// Everything one pair correlation needs besides the images and the points.
struct DicOptions {
  IcgnOptions icgn;         ///< subset size, shape order, iterations, tolerance, ZNCC and texture thresholds
  int step = 10;            ///< px between grid points, 1–1000
  int search_radius = 50;   ///< px, 1–10000: seed search window half-width (FFT cross-correlation)
  std::vector<Vec2> seeds;  ///< seed points in the reference image (px); empty = the point nearest the ROI centroid
  int max_seeds = 8;        ///< 1–1000: seed attempts per image pair before the unreached points are given up
  /// 0–1: a seed must reach this ZNCC (propagated points only need icgn.min_zncc). A Boolean-model speckle
  /// subset matches a look-alike elsewhere at ZNCC ≈ 0.9 and IC-GN can settle there from a poor start.
  double seed_min_zncc = 0.9;
  double prefilter_sigma = 0;  ///< px, 0–5: Gaussian pre-filter of every image (0 = none; ~0.5–1 reduces noise bias)
  int batch = 32;              ///< 1–4096: points propagated per round (in parallel); 1 = strict reliability order
  int threads = 0;             ///< OpenMP threads, 0 = OpenMP's default

  /// The config keys of [dic] these options hold besides icgn's (core/options.hpp); `seeds` is the
  /// verb's (a list of pixel pairs checked against the image).
  static auto keys() {
    using O = DicOptions;
    return std::tuple{
        option(&O::step, "dic.step", "Grid step in px between subset centres.", 1, 1000),
        option(&O::search_radius, "dic.search_radius", "px: how far the FFT cross-correlation seed search looks.", 1,
               10000),
        option(&O::max_seeds, "dic.max_seeds", "Seed attempts per image pair before unreached points are given up.", 1,
               1000),
        option(&O::seed_min_zncc, "dic.seed_min_zncc",
               "A seed must correlate at least this well (the points it spreads to need min_zncc).", 0, 1),
        option(&O::prefilter_sigma, "dic.prefilter_sigma",
               "px: Gaussian pre-filter of every image (0 = none; 0.5–1 lowers the noise-induced bias).", 0, 5),
        option(&O::batch, "dic.batch", "Points propagated per round (1 = strict highest-ZNCC-first order).", 1, 4096),
        option(&O::threads, "dic.threads",
               "OpenMP threads, 0 = all cores; more than the cores run as many as the cores.", 0, 1024)};
  }
  /// Throws InputError naming the key (`dic.step`, ...) when a field is out of range.
  void validate() const;
};

/// The matches of one image pair, index for index with the centres given.
struct PairResult {
  std::vector<PointMatch> points;
  int ok = 0;            ///< points with status ok
  double mean_zncc = 0;  ///< over ok points
  int seeds_tried = 0;   ///< seed attempts (0 when every point had a guess)
  double seconds = 0;    ///< wall time
  std::string message;   ///< one line: what happened (seeds, fall-backs)
  /// Subsets computed in each round of reliability-guided propagation (each round ends at a barrier):
  /// how parallel the propagation can be (bench/dic_benchmark.cpp models the 2-thread speed-up from it).
  std::vector<int> round_tasks;
};

/// Correlates subsets centred at `centres` in `reference` with `current`. `neighbours[k]` lists the
/// points next to k (−1 = none), which propagation follows. `guesses` (optional, per point) are
/// starting shapes, e.g. the previous frame's: points with a guess are computed in parallel from it
/// (at most 12 iterations), a result is kept only when a good neighbour's shape agrees with it
/// (`inconsistent` otherwise), and the rest is re-done by propagation from the kept points. Points no
/// guess reached start from seeds (DicOptions::seeds, else the untried point nearest the centroid):
/// FFT cross-correlation within search_radius, then, while no point of the pair is good, the wide
/// search of seed.hpp (at most twice). A seed must reach seed_min_zncc.
PairResult correlate_pair(const Frame& reference, const Frame& current, const std::vector<Vec2>& centres,
                          const std::vector<std::array<int, 4>>& neighbours, const DicOptions& options,
                          const std::vector<std::optional<Shape>>& guesses = {});

}  // namespace tricot::dic
