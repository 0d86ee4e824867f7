#pragma once
/// \file error.hpp
/// The one exception type pbd throws for invalid input; its message names the offending item.
#include <stdexcept>
#include <string>

namespace pbd {

/// Invalid input (file, key, line, index or value): what() names the item and what is wrong.
/// Whenever a call throws it, the world is left as it was before the call.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

}  // namespace pbd
