#pragma once
/// \file obj_loader.hpp
/// Triangle meshes from Wavefront OBJ files, read and checked in one pass; coordinates get exactly the values
/// tinyobjloader gives them (tests/io/obj_reference_test.cpp and the OBJ fuzzer compare the two).
#include "pbd/io/mesh.hpp"

#include <filesystem>
#include <string>

namespace pbd {

/// Largest OBJ file load_obj reads.
inline constexpr std::uintmax_t kMaxObjBytes = 256u << 20;

/// Loads the vertices ("v x y z", further values ignored) and faces ("f" with references v, v/vt, v//vn or v/vt/vn)
/// of every object in `file`; every other statement is ignored. Positions are welded by index; a polygon face of
/// n > 3 vertices is triangulated as a fan from its first vertex (right for convex polygons). Throws pbd::Error naming
/// the file and, for what is wrong inside it, the line ("pig.obj:12: ..."): a missing, empty (0 bytes), non-regular
/// or oversize file; a control byte (binary data); a vertex without 3 decimal coordinates, or one that is non-finite,
/// beyond float range or with an exponent beyond 400; a face with fewer than 3 vertices, a malformed reference, an
/// index 0 or out of range (negative = relative to the vertices before it, as OBJ says) or a vertex named twice;
/// no faces at all. Closedness is checked only where a volume asks for it (closed_mesh_defect in pbd/closed_mesh.hpp).
TriangleMesh load_obj(const std::filesystem::path& file);

/// Parses OBJ text as load_obj does (at most kMaxObjBytes); `source` names it in error messages.
TriangleMesh parse_obj(const std::string& text, const std::string& source);

}  // namespace pbd
