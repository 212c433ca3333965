// Measured figures go to the gtest report as test properties; docs/validation.md reads them from
// --gtest_output=json|xml, so the keys and the way each test writes its numbers must stay stable.
#pragma once

#include <gtest/gtest.h>

#include <ios>
#include <sstream>
#include <string>

namespace tricot::test {

/// Records `value` under `key` with `digits` significant digits, as a stream prints by default
/// ("0.00123", "1.23e-09").
inline void record(const std::string& key, double value, int digits = 3) {
  std::ostringstream o;
  o.precision(digits);
  o << value;
  ::testing::Test::RecordProperty(key, o.str());
}

/// Records `value` under `key` in scientific notation with `digits` significant digits ("1.23e-09").
inline void record_scientific(const std::string& key, double value, int digits = 3) {
  std::ostringstream o;
  o << std::scientific;
  o.precision(digits - 1);
  o << value;
  ::testing::Test::RecordProperty(key, o.str());
}

}  // namespace tricot::test
