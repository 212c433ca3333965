// Base64 text of bytes (RFC 4648, '=' padding): the VTU writer's binary arrays and the report's
// embedded figures. Written here: the few lines are not worth a dependency.
#pragma once

#include <string>
#include <string_view>

namespace tricot::io {

/// Standard base64 of `bytes`, with '=' padding.
std::string base64(std::string_view bytes);

}  // namespace tricot::io
