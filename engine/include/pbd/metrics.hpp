#pragma once
/// \file metrics.hpp
/// Error measures of a world's state: how far its constraints are from being satisfied.
#include "pbd/world.hpp"

namespace pbd {

/// RMS and maximum of a normalized violation over the constraints of one type (0 and 0 when there are none).
struct Violation {
  double rms = 0.0;        ///< root mean square
  double max = 0.0;        ///< maximum
  std::size_t count = 0;   ///< constraints measured
};

/// Relative stretch |(|x_a − x_b| − d)| / d of every stretch constraint (absolute length where d = 0).
template <class Real> Violation stretch_violation(const World<Real>& world);

/// Penetration depth max(0, −C) of every collider for every movable particle at the current positions.
template <class Real> Violation penetration(const World<Real>& world);

}  // namespace pbd
