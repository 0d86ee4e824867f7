#pragma once
/// \file build_world.hpp
/// A World<Real> from its precision-free description (world_description.hpp).
#include "pbd/io/world_description.hpp"
#include "pbd/world.hpp"

namespace pbd {

/// A World<Real> of `description`: Real(value) for every position, velocity, inverse mass, rest value, anchor target,
/// collider (with its material), contact body (radius, material) and step parameter, the constraints and contact
/// bodies in the description's order, time 0. Throws pbd::Error naming the
/// first value that is finite in double but not in Real (e.g. a position of 1e300 as float), and whatever
/// World<Real> refuses. Plane normals are normalized again in Real (exact for the axis-aligned unit normals of the
/// scene files; another unit normal may change in its last bit).
template <class Real> World<Real> build_world(const WorldDescription& description);

}  // namespace pbd
