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

/// `triangles` plus one line per stretch constraint whose particles are on no triangle.
template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<std::array<Index, 3>>& triangles);

/// Writes every particle as a vertex ("v x y z"), then the triangles ("f") and lines ("l"), 1-based. Throws
/// pbd::Error naming the file if it cannot be written.
template <class Real>
void write_obj_frame(const std::filesystem::path& file, const World<Real>& world, const FrameTopology& topology);

}  // namespace pbd
