#pragma once
// Builds error messages from any streamable parts (shared by the engine and pbd::io; not for hosts).
#include <sstream>
#include <string>

namespace pbd::detail {

template <class... Parts> std::string message(const Parts&... parts) {
  std::ostringstream s;
  s.precision(9);
  (s << ... << parts);
  return s.str();
}

}  // namespace pbd::detail
