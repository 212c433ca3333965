#include "tricot/core/format.hpp"

#include <cstdio>

namespace tricot {

std::string format_duration(double s) {
  char b[48];
  if (s < 1) std::snprintf(b, sizeof b, "%.0f ms", s * 1e3);
  else if (s < 60) std::snprintf(b, sizeof b, "%.1f s", s);
  else if (s < 3600) std::snprintf(b, sizeof b, "%d min %02d s", int(s) / 60, int(s) % 60);
  else std::snprintf(b, sizeof b, "%d h %02d min", int(s) / 3600, (int(s) % 3600) / 60);
  return b;
}

}  // namespace tricot
