#pragma once
/// \file frame_writer.hpp
/// Frames of a simulation as Wavefront OBJ files (readable by Blender and ParaView).
#include "pbd/world.hpp"

#include <filesystem>
#include <vector>

namespace pbd {

/// What a frame draws besides the particles: surface triangles and line segments.
struct FrameTopology {
  std::vector<std::array<Index, 3>> triangles;  ///< surface triangles (particle indices)
  std::vector<std::array<Index, 2>> lines;      ///< segments for bodies without triangles (ropes, particle chains)
};

/// `triangles` plus one line per stretch constraint whose two particles are both on no triangle. Throws pbd::Error
/// naming the triangle whose particle index is out of range.
template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<std::array<Index, 3>>& triangles);

/// Writes a header line ("# pbd frame: t = <time> s, <N> particles"), every particle as a vertex ("v x y z", %.7g, in
/// m), then the triangles ("f") and lines ("l"), 1-based. The file is written under a temporary name next to it and
/// renamed over it at the end, so a failure leaves no half-written frame. Throws pbd::Error naming the file if it
/// cannot be written, or naming the triangle or line whose particle index is out of range (nothing is written then).
template <class Real>
void write_obj_frame(const std::filesystem::path& file, const World<Real>& world, const FrameTopology& topology);

}  // namespace pbd
