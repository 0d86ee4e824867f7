#pragma once
// Base64 (RFC 4648, with '=' padding), as VTK XML files carry binary data arrays inline.
#include <string>
#include <string_view>

namespace pbd::detail {

/// Appends the base64 encoding of `bytes` to `out`.
void append_base64(std::string& out, std::string_view bytes);

}  // namespace pbd::detail
