#pragma once
// The mesh tinyobjloader reads from OBJ text, as pbd's loader used to get it: only the 'v' and 'f' statements (every
// other line left empty, so line numbers agree), no triangulation by tinyobjloader, each polygon then split as a fan
// from its first vertex. The reference the OBJ tests and the OBJ fuzzer compare load_obj with; only for text load_obj
// accepts (its checks keep tinyobjloader's integer overflows out).
#include "pbd/io/mesh.hpp"

#include <tiny_obj_loader.h>

#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace pbd::test {

/// The text pbd's loader gave tinyobjloader: per line, "v x y z" (the first three values only: tinyobjloader would
/// read more as a vertex colour) or "f" with the face's references separated by single spaces, every other line left
/// empty; lines end at "\n", "\r\n" or "\r" and come out ending at "\n".
inline std::string vertex_and_face_lines(const std::string& text) {
  std::string out;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t end = std::min(text.find_first_of("\r\n", pos), text.size());
    const std::string_view line = std::string_view(text).substr(pos, end - pos);
    std::vector<std::string_view> tokens;
    for (std::size_t at = line.find_first_not_of(" \t"); at != std::string_view::npos;
         at = line.find_first_not_of(" \t", at)) {
      const std::size_t stop = std::min(line.find_first_of(" \t", at), line.size());
      tokens.push_back(line.substr(at, stop - at));
      at = stop;
    }
    if (!tokens.empty() && (tokens[0] == "v" || tokens[0] == "f")) {
      const std::size_t n = tokens[0] == "v" ? std::min<std::size_t>(tokens.size(), 4) : tokens.size();
      for (std::size_t k = 0; k < n; ++k) {
        if (k > 0) out += ' ';
        out += tokens[k];
      }
    }
    out += '\n';
    pos = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
  }
  return out;
}

/// tinyobjloader's mesh of `text` (positions as the floats it stores, widened), or nothing if it fails.
inline std::optional<TriangleMesh> tinyobj_mesh(const std::string& text) {
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream stream(vertex_and_face_lines(text));
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, nullptr, /*triangulate=*/false))
    return std::nullopt;
  TriangleMesh mesh;
  const std::size_t nv = attrib.vertices.size() / 3;
  mesh.positions.resize(3, Eigen::Index(nv));
  for (std::size_t i = 0; i < nv; ++i)
    for (int d = 0; d < 3; ++d) mesh.positions(d, Eigen::Index(i)) = double(attrib.vertices[3 * i + std::size_t(d)]);
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (const auto count : shape.mesh.num_face_vertices) {
      const auto& idx = shape.mesh.indices;
      for (std::size_t k = 1; k + 1 < count; ++k)
        mesh.triangles.push_back({Index(idx[offset].vertex_index), Index(idx[offset + k].vertex_index),
                                  Index(idx[offset + k + 1].vertex_index)});
      offset += count;
    }
  }
  return mesh;
}

/// Whether `a` and `b` have the same positions, bit for bit (−0 is not 0), and the same triangles.
inline bool same_mesh(const TriangleMesh& a, const TriangleMesh& b) {
  return a.positions.cols() == b.positions.cols() && a.triangles == b.triangles &&
         std::memcmp(a.positions.data(), b.positions.data(), sizeof(double) * std::size_t(a.positions.size())) == 0;
}

}  // namespace pbd::test
