#include "pbd/io/obj_loader.hpp"

#include "message.hpp"
#include "pbd/error.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string_view>

namespace pbd {
namespace {

// What our own pass reads before tinyobjloader does. tinyobjloader reads "nan", a malformed number or a missing
// coordinate as 0, drops faces with fewer than 3 vertices, does not range-check indices, has signed overflows on
// some numbers and cannot say which line a face came from; so every 'v' and 'f' statement is checked here, with its
// line, and tinyobjloader only reads text that passed (its result is then compared with ours).
struct ObjScan {
  std::vector<std::size_t> vertex_line;  // line of each vertex, in file order
  std::vector<std::size_t> face_line;    // line of each face, in file order
  std::vector<std::size_t> face_begin;   // face f's vertices are refs[face_begin[f], face_begin[f + 1])
  std::vector<Index> refs;               // vertex indices, 0-based, resolved
  std::string checked;                   // the text for tinyobjloader: 'v' and 'f' lines, every other line empty
};

class ObjScanner {
public:
  explicit ObjScanner(const std::string& source) : source_(source) {}

  ObjScan scan(const std::string& text) {
    scan_.face_begin.push_back(0);
    std::size_t n = 0;
    // Lines end at "\n", "\r\n" or "\r", as tinyobjloader reads them, so the line numbers agree.
    for (std::size_t pos = 0; pos < text.size();) {
      const std::size_t end = std::min(text.find_first_of("\r\n", pos), text.size());
      statement(std::string_view(text).substr(pos, end - pos), ++n);
      scan_.checked += '\n';
      pos = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
    }
    // Positive indices may name a vertex defined further down the file: checked once every vertex is known.
    const std::size_t nv = scan_.vertex_line.size();
    for (std::size_t f = 0; f + 1 < scan_.face_begin.size(); ++f)
      for (std::size_t k = scan_.face_begin[f]; k < scan_.face_begin[f + 1]; ++k)
        if (scan_.refs[k] >= nv)
          fail(scan_.face_line[f], detail::message("vertex index ", std::size_t(scan_.refs[k]) + 1, " is out of range (the file has ",
                                                   nv, " vertices)"));
    // A face naming one vertex twice has a degenerate triangle (no normal, no area): a broken file.
    std::vector<std::size_t> seen(nv, 0);
    for (std::size_t f = 0; f + 1 < scan_.face_begin.size(); ++f)
      for (std::size_t k = scan_.face_begin[f]; k < scan_.face_begin[f + 1]; ++k) {
        if (seen[scan_.refs[k]] == f + 1)
          fail(scan_.face_line[f], detail::message("the face names vertex ", std::size_t(scan_.refs[k]) + 1, " twice"));
        seen[scan_.refs[k]] = f + 1;
      }
    return std::move(scan_);
  }

private:
  [[noreturn]] void fail(std::size_t line, const std::string& what) const {
    throw Error(detail::message(source_, ":", line, ": ", what));
  }

  static std::string shown(std::string_view token) {
    return std::string(token.substr(0, 40)) + (token.size() > 40 ? "..." : "");
  }

  void statement(std::string_view line, std::size_t n) {
    for (const char c : line) {
      const auto u = static_cast<unsigned char>(c);
      if ((u < 0x20 && c != '\t') || u == 0x7f)
        fail(n, detail::message("byte 0x", "0123456789abcdef"[u >> 4], "0123456789abcdef"[u & 15],
                                " is not text (is this a binary file?)"));
    }
    std::vector<std::string_view> tokens;  // separated by spaces and tabs, as tinyobjloader separates them
    for (std::size_t pos = line.find_first_not_of(" \t"); pos != std::string_view::npos;
         pos = line.find_first_not_of(" \t", pos)) {
      const std::size_t end = std::min(line.find_first_of(" \t", pos), line.size());
      tokens.push_back(line.substr(pos, end - pos));
      pos = end;
    }
    if (tokens.empty()) return;
    if (tokens[0] == "v") vertex(tokens, n);
    else if (tokens[0] == "f") face(tokens, n);
    // Anything else (comments, normals, texture coordinates, groups, materials, lines, points, tinyobjloader's
    // tags and skin weights, curves) is not used: left out of the text tinyobjloader reads.
  }

  // "v x y z [more values, ignored]"
  void vertex(const std::vector<std::string_view>& tokens, std::size_t n) {
    if (tokens.size() < 4) fail(n, detail::message("a vertex needs 3 coordinates, this one has ", tokens.size() - 1));
    scan_.checked += 'v';
    for (std::size_t d = 1; d <= 3; ++d) {
      number(tokens[d], n);
      scan_.checked += ' ';
      scan_.checked += tokens[d];
    }
    scan_.vertex_line.push_back(n);
  }

  // A decimal number that strtod and tinyobjloader read the same way: [+-] digits [. digits] [e [+-] digits] (or with
  // digits after the point only), finite, within float range (tinyobjloader stores floats) and with an exponent of
  // at most 400 in size (tinyobjloader overflows an int on a long exponent and reads 0e441 as 0 × inf = NaN).
  void number(std::string_view token, std::size_t n) const {
    std::size_t i = 0;
    auto digits = [&] {
      const std::size_t start = i;
      while (i < token.size() && token[i] >= '0' && token[i] <= '9') ++i;
      return token.substr(start, i - start);
    };
    if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
    std::size_t mantissa = digits().size();
    if (i < token.size() && token[i] == '.') {
      ++i;
      mantissa += digits().size();
    }
    std::string_view exponent = "0";
    if (mantissa > 0 && i < token.size() && (token[i] == 'e' || token[i] == 'E')) {
      ++i;
      if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
      exponent = digits();
    }
    if (mantissa == 0 || exponent.empty() || i != token.size())
      fail(n, detail::message("coordinate \"", shown(token), "\" is not a decimal number"));
    const double value = std::strtod(std::string(token).c_str(), nullptr);
    if (!std::isfinite(value)) fail(n, detail::message("coordinate \"", shown(token), "\" is not a finite number"));
    if (std::abs(value) > double(FLT_MAX))
      fail(n, detail::message("coordinate \"", shown(token), "\" is beyond the float range (3.4e38)"));
    while (exponent.size() > 1 && exponent[0] == '0') exponent.remove_prefix(1);
    if (exponent.size() > 3 || (exponent.size() == 3 && exponent > "400"))
      fail(n, detail::message("coordinate \"", shown(token), "\" has an exponent beyond 400"));
  }

  // "f v1 v2 v3 ..." with each reference v, v/vt, v//vn or v/vt/vn; only v is used.
  void face(const std::vector<std::string_view>& tokens, std::size_t n) {
    if (tokens.size() < 4)
      fail(n, detail::message("a face needs at least 3 vertices, this one has ", tokens.size() - 1));
    scan_.checked += 'f';
    for (std::size_t k = 1; k < tokens.size(); ++k) {
      const std::string_view ref = tokens[k];
      const std::size_t slash = ref.find('/');
      const long v = index(ref.substr(0, slash), ref, n);
      if (slash != std::string_view::npos) {
        const std::string_view rest = ref.substr(slash + 1);
        const std::size_t slash2 = rest.find('/');
        if (!(slash2 == 0 && rest.size() > 1)) index(rest.substr(0, slash2), ref, n);  // not "v//vn": vt
        if (slash2 != std::string_view::npos) index(rest.substr(slash2 + 1), ref, n);   // vn
      }
      const long defined = long(scan_.vertex_line.size());
      if (v < 0 && -v > defined)
        fail(n, detail::message("relative vertex index ", v, " is out of range (", defined,
                                " vertices are defined before this line)"));
      scan_.refs.push_back(Index(v > 0 ? v - 1 : defined + v));
      scan_.checked += ' ';
      scan_.checked += ref;
    }
    scan_.face_line.push_back(n);
    scan_.face_begin.push_back(scan_.refs.size());
  }

  // One index of a face reference: a non-zero integer that fits an int (tinyobjloader reads it with atoi).
  long index(std::string_view text, std::string_view ref, std::size_t n) const {
    std::size_t i = (!text.empty() && (text[0] == '+' || text[0] == '-')) ? 1 : 0;
    if (i == text.size() || text.find_first_not_of("0123456789", i) != std::string_view::npos)
      fail(n, detail::message("\"", shown(ref), "\" is not a vertex reference (v, v/vt, v//vn or v/vt/vn)"));
    while (i + 1 < text.size() && text[i] == '0') ++i;
    const long value = text.size() - i > 10 ? 1L << 40 : std::strtol(std::string(text).c_str(), nullptr, 10);
    if (value > 2147483647L || value < -2147483647L)
      fail(n, detail::message("index ", shown(text), " in \"", shown(ref), "\" is out of range"));
    if (value == 0) fail(n, detail::message("index 0 in \"", shown(ref), "\": OBJ indices start at 1"));
    return value;
  }

  const std::string& source_;
  ObjScan scan_;
};

}  // namespace

TriangleMesh load_obj(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status))
    throw Error(detail::message(name, ": cannot read the OBJ file (", ec ? ec.message() : "no such file", ")"));
  if (!std::filesystem::is_regular_file(status)) throw Error(name + ": cannot read the OBJ file (not a regular file)");
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) throw Error(detail::message(name, ": cannot read the OBJ file (", ec.message(), ")"));
  if (size == 0) throw Error(name + ": the file is empty (0 bytes)");
  if (size > kMaxObjBytes)
    throw Error(detail::message(name, ": file is ", size, " bytes, more than the ", kMaxObjBytes, " an OBJ may have"));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(name + ": cannot open the OBJ file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_obj(buffer.str(), name);
}

TriangleMesh parse_obj(const std::string& text, const std::string& name) {
  if (text.empty()) throw Error(name + ": the file is empty (0 bytes)");
  if (text.size() > kMaxObjBytes)
    throw Error(detail::message(name, ": ", text.size(), " bytes, more than the ", kMaxObjBytes, " an OBJ may have"));
  const ObjScan scan = ObjScanner(name).scan(text);
  if (scan.face_line.empty()) throw Error(name + ": the file has no faces");

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream stream(scan.checked);
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, nullptr, /*triangulate=*/false);
  if (!ok) {
    // tinyobjloader's messages carry the line ("... line 12.)").
    std::string what = err.empty() ? std::string("malformed OBJ") : err;
    while (!what.empty() && (what.back() == '\n' || what.back() == '.')) what.pop_back();
    throw Error(name + ": " + what);
  }
  const std::size_t nv = attrib.vertices.size() / 3;
  if (nv != scan.vertex_line.size())
    throw Error(detail::message(name, ": read ", nv, " vertices but the file has ", scan.vertex_line.size()));
  TriangleMesh mesh;
  mesh.positions.resize(3, Eigen::Index(nv));
  for (std::size_t i = 0; i < nv; ++i) {
    for (int d = 0; d < 3; ++d) mesh.positions(d, Eigen::Index(i)) = double(attrib.vertices[3 * i + d]);
    if (!mesh.positions.col(Eigen::Index(i)).allFinite())
      throw Error(detail::message(name, ":", scan.vertex_line[i], ": could not read this vertex as finite numbers"));
  }
  std::size_t face = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (const auto count : shape.mesh.num_face_vertices) {
      if (face >= scan.face_line.size())
        throw Error(detail::message(name, ": read more faces than the file has (", scan.face_line.size(), ")"));
      const std::size_t begin = scan.face_begin[face], end = scan.face_begin[face + 1];
      bool same = count == end - begin && offset + count <= shape.mesh.indices.size();
      for (std::size_t k = 0; same && k < count; ++k)
        same = shape.mesh.indices[offset + k].vertex_index == int(scan.refs[begin + k]);
      if (!same) throw Error(detail::message(name, ":", scan.face_line[face], ": could not read every vertex of this face"));
      for (std::size_t k = begin + 1; k + 1 < end; ++k)
        mesh.triangles.push_back({scan.refs[begin], scan.refs[k], scan.refs[k + 1]});
      offset += count;
      ++face;
    }
  }
  if (face != scan.face_line.size())
    throw Error(detail::message(name, ": read ", face, " faces but the file has ", scan.face_line.size(), " face lines"));
  return mesh;
}

}  // namespace pbd
