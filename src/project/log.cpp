#include "tricot/project/log.hpp"

#include <fmt/format.h>

namespace tricot::project {

std::string format_duration(double s) {
  if (s < 1) return fmt::format("{:.0f} ms", s * 1e3);
  if (s < 60) return fmt::format("{:.1f} s", s);
  if (s < 3600) return fmt::format("{} min {:02d} s", int(s) / 60, int(s) % 60);
  return fmt::format("{} h {:02d} min", int(s) / 3600, (int(s) % 3600) / 60);
}

}  // namespace tricot::project
