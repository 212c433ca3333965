#include "tricot/core/options.hpp"

#include <cmath>

#include <fmt/format.h>

#include "tricot/core/error.hpp"

namespace tricot {

std::string range_text(double min, double max) {
  const bool lo = std::isfinite(min), hi = std::isfinite(max);
  if (lo && hi) return fmt::format("{} to {}", min, max);
  if (lo) return fmt::format(">= {}", min);
  if (hi) return fmt::format("<= {}", max);
  return {};
}

namespace detail {

void throw_out_of_range(std::string_view key, double got, bool integer, double min, double max) {
  std::string text = integer ? fmt::format("{}", static_cast<long long>(got)) : fmt::format("{}", got);
  if (!integer && std::isfinite(got) && text.find_first_of(".eE") == std::string::npos) text += ".0";
  throw InputError(Location{"", 0, std::string(key)}, std::isfinite(got) ? "out of range" : "must be a finite number",
                   text, range_text(min, max));
}

void throw_not_a_word(std::string_view key, std::string_view got, const std::vector<std::string_view>& words) {
  std::string expected = "one of ";
  for (std::size_t i = 0; i < words.size(); ++i) expected += (i ? ", " : "") + std::string(words[i]);
  throw InputError(Location{"", 0, std::string(key)}, "not a valid choice", "\"" + std::string(got) + "\"", expected);
}

}  // namespace detail
}  // namespace tricot
