#pragma once
/// \file obj_loader.hpp
/// Triangle meshes from Wavefront OBJ files (parsed with tinyobjloader, then checked).
#include "pbd/mesh.hpp"

#include <filesystem>

namespace pbd {

/// Largest OBJ file load_obj reads.
inline constexpr std::uintmax_t kMaxObjBytes = 256u << 20;

/// Loads the vertices and faces of every object in `file`. Positions are welded by index (texture coordinates and
/// normals are ignored); a polygon face of n > 3 vertices is triangulated as a fan from its first vertex (right for
/// convex polygons). Throws pbd::Error naming the file (and the line where it can) for: a missing or oversize file,
/// a malformed line, a face with fewer than 3 vertices or an index 0 or out of range (negative = relative, as OBJ
/// says), a non-finite coordinate, or no faces at all. Closedness is checked only where a volume asks for it
/// (closed_mesh_defect).
TriangleMesh load_obj(const std::filesystem::path& file);

}  // namespace pbd
