#pragma once
/// \file finite_state.hpp
/// The check every frame writer makes before it writes: a frame holds only finite values (a NaN written as "-nan" is
/// a file pbd's own OBJ loader refuses). A step never leaves a non-finite state (World::step), but a host may write
/// one through positions() or velocities() between steps.
#include "pbd/world.hpp"

#include <string>

namespace pbd {

/// Throws pbd::Error "<what>: particle <i> has a non-finite position (x, y, z)" (or velocity) naming the first such
/// particle, unless every position and velocity of `world` is finite.
template <class Real> void check_finite_state(const World<Real>& world, const std::string& what);

}  // namespace pbd
