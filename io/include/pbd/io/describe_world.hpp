#pragma once
/// \file describe_world.hpp
/// The precision-free description (world_description.hpp) of an existing world.
#include "pbd/io/world_description.hpp"
#include "pbd/world.hpp"

namespace pbd {

/// The description of `world` as it is now (current positions and velocities; colliders with their materials and
/// contact bodies included; time, user-defined constraint types and solver settings are not described):
/// build_world<double>(describe_world(w)) is w in double.
template <class Real> WorldDescription describe_world(const World<Real>& world);

}  // namespace pbd
