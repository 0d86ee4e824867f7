#pragma once
/// \file frame_writer.hpp
/// Frames of a simulation as Wavefront OBJ files, one object per body (readable by Blender and ParaView).
#include "pbd/io/frame_topology.hpp"
#include "pbd/world.hpp"

#include <filesystem>
#include <string>

namespace pbd {

/// The text of an OBJ frame: a header line ("# pbd frame: t = <time> s, <N> particles"), then per body an object
/// line "o <name>" (bytes up to the space replaced by '_'), its particles as vertices ("v x y z", %.7g, in m), its
/// triangles ("f") and its lines ("l"), but not its tets: OBJ has no volume cells, so a tet body is its boundary
/// triangles, its interior particles vertices no face uses. Indices are 1-based over the whole file, so vertex i + 1
/// is particle i.
/// Throws pbd::Error naming `what` if the topology does not fit the world (check_frame_topology), or naming the first
/// particle whose position or velocity is not finite (check_finite_state).
template <class Real> std::string obj_frame(const World<Real>& world, const FrameTopology& topology, const std::string& what);

/// Writes obj_frame to `file` through write_file_atomically: a failure leaves no half-written frame and no temporary.
/// Throws pbd::Error naming the file if it cannot be written, or naming the body, triangle or line that does not fit
/// the world (nothing is written then).
template <class Real>
void write_obj_frame(const std::filesystem::path& file, const World<Real>& world, const FrameTopology& topology);

}  // namespace pbd
