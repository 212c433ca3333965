// Mirror boundary of the image engine, shared by the B-spline pre-filter and the Gaussian blur.
// Private to tricot_image.
#pragma once

namespace tricot::image::detail {

/// Mirror index (whole-sample symmetric) into [0, n): −1 → 1, n → n − 2.
inline int mirror(int i, int n) {
  if (n == 1) return 0;
  const int period = 2 * (n - 1);
  i %= period;
  if (i < 0) i += period;
  return i < n ? i : period - i;
}

}  // namespace tricot::image::detail
