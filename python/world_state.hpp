#pragma once
// A world's description (io's world_description.hpp) as bytes and back: what pickling a World stores. The bytes
// are the description's values in order (native byte order, as pickles of numpy arrays are), after a tag and a
// format version; reading checks both and every count against what is left, and throws pbd::Error naming the
// first thing that does not fit.
#include "pbd/io/world_description.hpp"

#include <string>
#include <string_view>

namespace pbd::python {

/// The bytes of `d`.
std::string save_description(const WorldDescription& d);

/// The description in `bytes` (made by save_description); pbd::Error if they are not one.
WorldDescription load_description(std::string_view bytes);

}  // namespace pbd::python
