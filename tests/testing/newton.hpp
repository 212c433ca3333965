// Convergence order of a Newton residual history (issue 2: "Newton converges quadratically").
#pragma once

#include <cmath>
#include <vector>

namespace tricot::test {

/// Order log(r_k/r_k−1)/log(r_k−1/r_k−2) from the last three residuals above `floor` (round-off);
/// NaN when fewer than three are.
inline double convergence_order(const std::vector<double>& residuals, double floor) {
  std::vector<double> v;
  for (double x : residuals)
    if (x > floor) v.push_back(x);
  if (v.size() < 3) return NAN;
  const size_t k = v.size() - 2;
  return std::log(v[k + 1] / v[k]) / std::log(v[k] / v[k - 1]);
}

}  // namespace tricot::test
