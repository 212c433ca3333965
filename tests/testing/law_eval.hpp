// One-call evaluations of a fem::Law for the law tests (tests/fem only: needs tricot_fem).
#pragma once

#include "tricot/fem/law.hpp"

namespace tricot::test {

/// P alone at F with material axes Q.
inline Mat2 P_of(const fem::Law& law, const Mat2& F, const Mat2& Q) {
  fem::LawOutput out;
  law.evaluate({F, Q}, {false, false}, out);
  return out.P;
}

/// P, A and λ3 at F (material axes = identity), and ∂P/∂c when `sensitivities`.
inline fem::LawOutput eval(const fem::Law& law, const Mat2& F, bool sensitivities = false) {
  fem::LawInput in;
  in.F = F;
  fem::LawOutput out;
  law.evaluate(in, fem::LawRequest{true, sensitivities}, out);
  return out;
}

}  // namespace tricot::test
