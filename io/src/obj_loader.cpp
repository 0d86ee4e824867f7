#include "pbd/io/obj_loader.hpp"

#include "pbd/detail/message.hpp"
#include "obj_number.hpp"
#include "pbd/error.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string_view>

namespace pbd {
namespace {

// One pass over the text reads every 'v' and 'f' statement and checks it, with its line: tinyobjloader, which
// loaded the meshes before, reads "nan", a malformed number or a missing coordinate as 0, drops faces with fewer
// than 3 vertices, does not range-check indices, has signed overflows on some numbers and cannot say which line a
// face came from, and parsing everything a second time cost more than the whole check. Coordinates get exactly
// tinyobjloader's values (obj_number.hpp; tests/io compare the two, and so does the OBJ fuzzer).
// Line numbers and counts fit 32 bits: a text of at most kMaxObjBytes has fewer lines and references.
struct ObjScan {
  std::vector<std::uint32_t> vertex_line;  // line of each vertex, in file order
  std::vector<float> coordinates;          // x, y, z of each vertex as tinyobjloader stores them
  std::vector<std::uint32_t> face_line;    // line of each face, in file order
  std::vector<std::uint32_t> face_begin;   // face f's vertices are refs[face_begin[f], face_begin[f + 1])
  std::vector<Index> refs;                 // vertex indices, 0-based, resolved
};

bool is_space(char c) { return c == ' ' || c == '\t'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

class ObjScanner {
public:
  explicit ObjScanner(const std::string& source) : source_(source) {}

  ObjScan scan(std::string_view text) {
    // Room for every line being a vertex and every line a face: address space only, as pages are touched when
    // written; no array is grown and copied while reading.
    const std::size_t lines = std::size_t(std::count(text.begin(), text.end(), '\n')) + 1;
    scan_.vertex_line.reserve(lines);
    scan_.coordinates.reserve(3 * lines);
    scan_.face_line.reserve(lines);
    scan_.face_begin.reserve(lines + 1);
    scan_.refs.reserve(3 * lines);
    scan_.face_begin.push_back(0);
    std::size_t n = 0;
    // Lines end at "\n", "\r\n" or "\r", as tinyobjloader reads them, so the line numbers agree.
    const char* const data = text.data();
    const std::size_t size = text.size();
    for (std::size_t pos = 0; pos < size;) {
      std::size_t end = pos;
      std::size_t control = std::string::npos;  // the first byte that is not text, if any
      for (; end < size; ++end) {
        const auto u = static_cast<unsigned char>(data[end]);
        if (u >= 0x20 && u != 0x7f) continue;
        if (u == '\n' || u == '\r') break;
        if (u != '\t' && control == std::string::npos) control = end;
      }
      ++n;
      if (control != std::string::npos) {
        const auto u = static_cast<unsigned char>(data[control]);
        fail(n, detail::message("byte 0x", "0123456789abcdef"[u >> 4], "0123456789abcdef"[u & 15],
                                " is not text (is this a binary file?)"));
      }
      statement(std::string_view(data + pos, end - pos), n);
      pos = end + (end + 1 < size && data[end] == '\r' && data[end + 1] == '\n' ? 2 : 1);
    }
    // Positive indices may name a vertex defined further down the file: checked once every vertex is known.
    const std::size_t nv = scan_.vertex_line.size();
    for (std::size_t f = 0; f + 1 < scan_.face_begin.size(); ++f)
      for (std::size_t k = scan_.face_begin[f]; k < scan_.face_begin[f + 1]; ++k)
        if (scan_.refs[k] >= nv)
          fail(scan_.face_line[f], detail::message("vertex index ", std::size_t(scan_.refs[k]) + 1, " is out of range (the file has ",
                                                   nv, " vertices)"));
    // A face naming one vertex twice has a degenerate triangle (no normal, no area): a broken file.
    std::vector<std::uint32_t> seen(nv, 0);
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
    tokens_.clear();  // separated by spaces and tabs, as tinyobjloader separates them
    for (std::size_t pos = 0; pos < line.size();) {
      while (pos < line.size() && is_space(line[pos])) ++pos;
      if (pos == line.size()) break;
      const std::size_t start = pos;
      while (pos < line.size() && !is_space(line[pos])) ++pos;
      tokens_.push_back(line.substr(start, pos - start));
      if (tokens_.size() == 1 && tokens_[0] != "v" && tokens_[0] != "f") return;
    }
    if (tokens_.empty()) return;
    if (tokens_[0] == "v") vertex(n);
    else face(n);
    // Anything else (comments, normals, texture coordinates, groups, materials, lines, points, tinyobjloader's
    // tags and skin weights, curves) is not used.
  }

  // "v x y z [more values, ignored]"
  void vertex(std::size_t n) {
    if (tokens_.size() < 4) fail(n, detail::message("a vertex needs 3 coordinates, this one has ", tokens_.size() - 1));
    for (std::size_t d = 1; d <= 3; ++d) {
      number(tokens_[d], n);
      scan_.coordinates.push_back(static_cast<float>(detail::obj_number(tokens_[d])));
    }
    scan_.vertex_line.push_back(std::uint32_t(n));
  }

  // A decimal number that strtod and tinyobjloader read the same way: [+-] digits [. digits] [e [+-] digits] (or with
  // digits after the point only), finite, within float range (tinyobjloader stores floats) and with an exponent of
  // at most 400 in size (tinyobjloader overflows an int on a long exponent and reads 0e441 as 0 × inf = NaN).
  void number(std::string_view token, std::size_t n) const {
    std::size_t i = 0;
    std::size_t integer_digits = 0;  // without leading zeros
    auto digits = [&] {
      const std::size_t start = i;
      while (i < token.size() && is_digit(token[i])) ++i;
      return token.substr(start, i - start);
    };
    if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
    std::string_view integer = digits();
    std::size_t mantissa = integer.size();
    while (!integer.empty() && integer[0] == '0') integer.remove_prefix(1);
    integer_digits = integer.size();
    if (i < token.size() && token[i] == '.') {
      ++i;
      mantissa += digits().size();
    }
    std::string_view exponent = "0";
    bool exponent_negative = false;
    if (mantissa > 0 && i < token.size() && (token[i] == 'e' || token[i] == 'E')) {
      ++i;
      if (i < token.size() && (token[i] == '+' || token[i] == '-')) exponent_negative = token[i++] == '-';
      exponent = digits();
    }
    if (mantissa == 0 || exponent.empty() || i != token.size())
      fail(n, detail::message("coordinate \"", shown(token), "\" is not a decimal number"));
    while (exponent.size() > 1 && exponent[0] == '0') exponent.remove_prefix(1);
    // Below 10^30 in size, with an exponent of at most two digits: finite, in float range, nothing to report.
    if (exponent.size() <= 2) {
      const long e = exponent.size() == 1 ? long(exponent[0] - '0') : long(exponent[0] - '0') * 10 + (exponent[1] - '0');
      if (long(integer_digits) + (exponent_negative ? -e : e) <= 30) return;
    }
    const double value = std::strtod(std::string(token).c_str(), nullptr);
    if (!std::isfinite(value)) fail(n, detail::message("coordinate \"", shown(token), "\" is not a finite number"));
    if (std::abs(value) > double(FLT_MAX))
      fail(n, detail::message("coordinate \"", shown(token), "\" is beyond the float range (3.4e38)"));
    if (exponent.size() > 3 || (exponent.size() == 3 && exponent > "400"))
      fail(n, detail::message("coordinate \"", shown(token), "\" has an exponent beyond 400"));
  }

  // "f v1 v2 v3 ..." with each reference v, v/vt, v//vn or v/vt/vn; only v is used.
  void face(std::size_t n) {
    if (tokens_.size() < 4)
      fail(n, detail::message("a face needs at least 3 vertices, this one has ", tokens_.size() - 1));
    for (std::size_t k = 1; k < tokens_.size(); ++k) {
      const std::string_view ref = tokens_[k];
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
    }
    scan_.face_line.push_back(std::uint32_t(n));
    scan_.face_begin.push_back(std::uint32_t(scan_.refs.size()));
  }

  // One index of a face reference: a non-zero integer that fits an int (tinyobjloader reads it with atoi).
  long index(std::string_view text, std::string_view ref, std::size_t n) const {
    std::size_t i = (!text.empty() && (text[0] == '+' || text[0] == '-')) ? 1 : 0;
    const bool negative = i == 1 && text[0] == '-';
    if (i == text.size()) fail(n, detail::message("\"", shown(ref), "\" is not a vertex reference (v, v/vt, v//vn or v/vt/vn)"));
    for (std::size_t j = i; j < text.size(); ++j)
      if (!is_digit(text[j]))
        fail(n, detail::message("\"", shown(ref), "\" is not a vertex reference (v, v/vt, v//vn or v/vt/vn)"));
    while (i + 1 < text.size() && text[i] == '0') ++i;
    long value = 1L << 40;  // more than 10 digits: out of range
    if (text.size() - i <= 10) {
      value = 0;
      for (std::size_t j = i; j < text.size(); ++j) value = value * 10 + (text[j] - '0');
      if (negative) value = -value;
    }
    if (value > 2147483647L || value < -2147483647L)
      fail(n, detail::message("index ", shown(text), " in \"", shown(ref), "\" is out of range"));
    if (value == 0) fail(n, detail::message("index 0 in \"", shown(ref), "\": OBJ indices start at 1"));
    return value;
  }

  const std::string& source_;
  ObjScan scan_;
  std::vector<std::string_view> tokens_;  // of the current statement (kept: no allocation per line)
};

TriangleMesh parse_obj_text(std::string_view text, const std::string& name);  // below

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
  // Read at once into a buffer nothing fills first: a file of hundreds of MB is neither copied nor zeroed again.
  const std::unique_ptr<char[]> buffer(new char[std::size_t(size)]);
  in.read(buffer.get(), std::streamsize(size));
  if (in.bad()) throw Error(name + ": cannot read the OBJ file (read error)");
  const std::size_t read = std::size_t(in.gcount());
  if (read == 0) throw Error(name + ": the file is empty (0 bytes)");
  return parse_obj_text(std::string_view(buffer.get(), read), name);
}

TriangleMesh parse_obj(const std::string& text, const std::string& name) { return parse_obj_text(text, name); }

namespace {

TriangleMesh parse_obj_text(std::string_view text, const std::string& name) {
  if (text.empty()) throw Error(name + ": the file is empty (0 bytes)");
  if (text.size() > kMaxObjBytes)
    throw Error(detail::message(name, ": ", text.size(), " bytes, more than the ", kMaxObjBytes, " an OBJ may have"));
  const ObjScan scan = ObjScanner(name).scan(text);
  if (scan.face_line.empty()) throw Error(name + ": the file has no faces");
  const std::size_t nv = scan.vertex_line.size();
  TriangleMesh mesh;
  mesh.positions.resize(3, Eigen::Index(nv));
  for (std::size_t i = 0; i < nv; ++i) {
    // Stored as float, as tinyobjloader stores them, then widened.
    for (int d = 0; d < 3; ++d)
      mesh.positions(d, Eigen::Index(i)) = double(scan.coordinates[3 * i + std::size_t(d)]);
    if (!mesh.positions.col(Eigen::Index(i)).allFinite())
      throw Error(detail::message(name, ":", scan.vertex_line[i], ": could not read this vertex as finite numbers"));
  }
  mesh.triangles.reserve(scan.refs.size() - 2 * scan.face_line.size());
  for (std::size_t f = 0; f < scan.face_line.size(); ++f) {
    const std::size_t begin = scan.face_begin[f], end = scan.face_begin[f + 1];
    // tinyobjloader keeps a face's vertex count in a byte; the files it could not read stay refused.
    if (end - begin > 255)
      throw Error(detail::message(name, ":", scan.face_line[f], ": could not read every vertex of this face (it has ",
                                  end - begin, "; at most 255 are read)"));
    for (std::size_t k = begin + 1; k + 1 < end; ++k) mesh.triangles.push_back({scan.refs[begin], scan.refs[k], scan.refs[k + 1]});
  }
  return mesh;
}

}  // namespace
}  // namespace pbd
