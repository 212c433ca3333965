// How every summary line shows a duration (the CLI's progress lines, IdentifyResult::brief_report()).
#pragma once

#include <string>

namespace tricot {

/// "1 h 02 min", "3 min 20 s", "12.3 s", "85 ms".
std::string format_duration(double seconds);

}  // namespace tricot
