#pragma once
// The value tinyobjloader gives a decimal number of an OBJ file (private to pbd::io).
#include <string_view>

namespace pbd::detail {

/// The double tinyobjloader (2.0.0rc10, tryParseDouble) reads from `token`, operation for operation, so that a mesh
/// keeps the bits it had when tinyobjloader parsed it: the digits accumulated in double (integer digits as m·10 + d,
/// the k-th fraction digit as d·10^−k), then m·5^e scaled by 2^e for an exponent e ≠ 0. `token` must be a checked
/// decimal number: [+-] digits [. [digits]] [(e|E) [+-] digits], or [+-] . digits [(e|E) [+-] digits].
double obj_number(std::string_view token);

}  // namespace pbd::detail
