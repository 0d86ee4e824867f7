#include "pbd/obj_loader.hpp"

#include "message.hpp"
#include "pbd/error.hpp"

#include <tiny_obj_loader.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace pbd {
namespace {

// Line number (1-based) of each 'f' record of the text, in file order, and its number of vertex references.
struct FaceLine {
  std::size_t line;
  std::size_t count;
};

// Also checks every 'v' record: tinyobjloader reads "nan" or a malformed number as 0 without a word.
std::vector<FaceLine> face_lines(const std::string& text, const std::string& name) {
  std::vector<FaceLine> out;
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    const std::size_t k = line.find_first_not_of(" \t");
    if (k == std::string::npos || k + 1 >= line.size() || (line[k + 1] != ' ' && line[k + 1] != '\t')) continue;
    std::istringstream tokens(line.substr(k + 1));
    std::string tok;
    if (line[k] == 'f') {
      std::size_t count = 0;
      while (tokens >> tok) ++count;
      out.push_back({n, count});
    } else if (line[k] == 'v') {
      for (int d = 0; d < 3; ++d) {
        if (!(tokens >> tok)) throw Error(detail::message(name, ":", n, ": a vertex needs 3 coordinates"));
        char* end = nullptr;
        const double value = std::strtod(tok.c_str(), &end);
        if (end == tok.c_str() || *end != '\0' || !std::isfinite(value))
          throw Error(detail::message(name, ":", n, ": coordinate \"", tok, "\" is not a finite number"));
      }
    }
  }
  return out;
}

}  // namespace

TriangleMesh load_obj(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) throw Error(detail::message(name, ": cannot read the OBJ file (", ec.message(), ")"));
  if (size > kMaxObjBytes)
    throw Error(detail::message(name, ": file is ", size, " bytes, more than the ", kMaxObjBytes, " an OBJ may have"));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(name + ": cannot open the OBJ file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();

  // Our own pass first: tinyobjloader silently drops faces with fewer than 3 vertices and cannot say which line a
  // face came from, so count each face's references and remember its line.
  const std::vector<FaceLine> lines = face_lines(text, name);
  for (const FaceLine& f : lines)
    if (f.count < 3)
      throw Error(detail::message(name, ":", f.line, ": a face needs at least 3 vertices, this one has ", f.count));

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream stream(text);
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, nullptr, /*triangulate=*/false);
  if (!ok) {
    // tinyobjloader's messages carry the line ("... line 12.)").
    std::string what = err.empty() ? std::string("malformed OBJ") : err;
    while (!what.empty() && (what.back() == '\n' || what.back() == '.')) what.pop_back();
    throw Error(name + ": " + what);
  }
  const std::size_t nv = attrib.vertices.size() / 3;
  TriangleMesh mesh;
  mesh.positions.resize(3, Eigen::Index(nv));
  for (std::size_t i = 0; i < nv; ++i) {
    for (int d = 0; d < 3; ++d) mesh.positions(d, Eigen::Index(i)) = double(attrib.vertices[3 * i + d]);
    if (!mesh.positions.col(Eigen::Index(i)).allFinite())
      throw Error(detail::message(name, ": vertex ", i + 1, " has a non-finite coordinate"));
  }
  std::size_t face = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (const auto count : shape.mesh.num_face_vertices) {
      const std::size_t line = face < lines.size() ? lines[face].line : 0;
      const std::string where = line ? detail::message(name, ":", line) : detail::message(name, ": face ", face + 1);
      std::vector<Index> ids;
      for (std::size_t k = 0; k < count; ++k) {
        const int v = shape.mesh.indices[offset + k].vertex_index;
        if (v < 0 || std::size_t(v) >= nv)
          throw Error(detail::message(where, ": vertex index out of range (", nv, " vertices are defined)"));
        ids.push_back(Index(v));
      }
      if (line && count != lines[face].count)
        throw Error(detail::message(where, ": could not read every vertex of this face"));
      for (std::size_t k = 1; k + 1 < ids.size(); ++k) mesh.triangles.push_back({ids[0], ids[k], ids[k + 1]});
      offset += count;
      ++face;
    }
  }
  if (face != lines.size())
    throw Error(detail::message(name, ": read ", face, " faces but the file has ", lines.size(), " face lines"));
  if (mesh.triangles.empty()) throw Error(name + ": the file has no faces");
  return mesh;
}

}  // namespace pbd
