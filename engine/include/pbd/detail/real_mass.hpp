#pragma once
// A mass given in double as the world's Real (shared by the engine's callers in pbd::io and Python; not for hosts).
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <cmath>
#include <cstddef>

namespace pbd::detail {

/// `mass` (kg) as Real, for particle `index` of call `fn`: a finite mass Real cannot hold (1e39 in float) is a
/// pbd::Error, where the conversion would make it infinity, the mass of a pinned particle. (check_mass then refuses
/// one whose inverse Real cannot hold.)
template <class Real> Real real_mass(double mass, const char* fn, std::size_t index) {
  if (std::isfinite(mass) && !std::isfinite(Real(mass)))
    throw Error(message(fn, ": particle ", index, ": mass ", mass, " kg is beyond the range of ",
                        sizeof(Real) == 4 ? "float" : "double", " (only kPinned, infinity, pins a particle)"));
  return Real(mass);
}

}  // namespace pbd::detail
