// Synthetic measurements from an FE run (issue: `tricot synth`): what an experiment would have
// measured if the material followed the model exactly, optionally with Gaussian noise. Generate on a
// finer mesh than the one identified on, so that the test is not an inverse crime.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "tricot/fem/model.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/experiment.hpp"

namespace tricot::ident {

/// The test's data as the FE run `sim` of `model` gives them: loads, edge displacement and force
/// per step, and u, v at `points` (mm, model coordinates) as `kind` measures them (docs/theory.md §7).
/// `ids` default to 0, 1, …. Throws InputError when `sim` is not usable or a point is outside the
/// mesh (reference mesh; for incremental data, a deformed one).
TestData measure(const fem::TestModel& model, const fem::SimulationResult& sim, const Eigen::Matrix2Xd& points,
                 std::vector<int> ids = {}, FieldKind kind = FieldKind::cumulative);

/// Adds independent Gaussian noise of standard deviation σ to every measured value of each
/// quantity (σ = 0 leaves it as is), reproducibly for a given seed, and records σ in data.sigma.
void add_noise(TestData& data, const Sigma& sigma, std::uint64_t seed);

/// σ per quantity as a fraction of its RMS over the test (e.g. 0.005 for "0.5 % noise").
Sigma rms_fraction(const TestData& data, double fraction);

}  // namespace tricot::ident
