// What a law returns where F is no deformation (det F ≤ 0 or not finite): NaN in every output, so
// that the solver reports an invalid state instead of using a number. Private to tricot_fem.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "tricot/fem/law.hpp"

namespace tricot::fem::detail {

/// True, with NaN in P, A, λ3 (and the `n_coefficients` ∂P/∂c when asked), when `detF` ≤ 0 or is not finite.
inline bool invalid_state(double detF, const LawRequest& req, std::size_t n_coefficients, LawOutput& out) {
  if (detF > 0 && std::isfinite(detF)) return false;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.P.setConstant(nan);
  out.A.setConstant(nan);
  out.lambda3 = nan;
  out.dP_dc.assign(req.sensitivities ? n_coefficients : 0, Mat2::Constant(nan));
  return true;
}

}  // namespace tricot::fem::detail
