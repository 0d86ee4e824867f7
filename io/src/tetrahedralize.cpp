#include "pbd/io/tetrahedralize.hpp"
#include "pbd/io/tet_mesh_reader.hpp"

#include "pbd/closed_mesh.hpp"
#include "pbd/constraints/degenerate.hpp"
#include "pbd/constraints/volume.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <vector>

extern char** environ;

namespace pbd {
namespace {

using detail::message;

// At most about this many tets: a smaller max_volume is refused before tetgen runs (it would take minutes and
// gigabytes, and the text files alone would be hundreds of megabytes).
constexpr double kMaxTets = 1e7;

// A directory of our own under the system's temporary directory (mkdtemp: a fresh name, mode 0700), removed with
// everything in it when the object goes, on every path out of tetrahedralize.
class ScratchDir {
public:
  explicit ScratchDir(const std::string& source) {
    std::error_code ec;
    const std::filesystem::path base = std::filesystem::temp_directory_path(ec);
    if (ec) throw Error(message(source, ": no temporary directory for tetgen (", ec.message(), ")"));
    std::string name = (base / "pbd_tetgen_XXXXXX").string();
    if (::mkdtemp(name.data()) == nullptr)
      throw Error(message(source, ": cannot create a temporary directory for tetgen in ", base.string(), " (",
                          std::strerror(errno), ")"));
    path_ = name;
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

private:
  std::filesystem::path path_;
};

// Shortest text of `x` that reads back as exactly `x`, or with max_digits10 significant digits: std::to_chars, so
// independent of the locale.
std::string number_text(double x, std::chars_format format, std::optional<int> precision = std::nullopt) {
  char buffer[400];
  const auto r = precision ? std::to_chars(buffer, buffer + sizeof buffer, x, format, *precision)
                           : std::to_chars(buffer, buffer + sizeof buffer, x, format);
  return std::string(buffer, r.ptr);
}

// The surface as a TetGen .smesh file: its vertices (numbered from 0) and one facet per triangle, no holes, no
// regions. Coordinates with max_digits10 significant digits, which tetgen reads with strtod: exactly our doubles.
// (.smesh is TetGen's own format for a surface, read by -p; .off and .stl would do too, but .stl repeats each
// vertex per triangle and leaves tetgen to weld them.)
void write_smesh(const std::filesystem::path& file, const TriangleMesh& surface, const std::string& source) {
  std::string text = message("# written by pbd::tetrahedralize\n", surface.num_vertices(), " 3 0 0\n");
  const int digits = std::numeric_limits<double>::max_digits10;
  for (Index v = 0; v < surface.num_vertices(); ++v) {
    text += std::to_string(v);
    for (int d = 0; d < 3; ++d) text += ' ' + number_text(surface.positions(d, v), std::chars_format::general, digits);
    text += '\n';
  }
  text += message(surface.triangles.size(), " 0\n");
  for (const auto& t : surface.triangles) text += message("3 ", t[0], ' ', t[1], ' ', t[2], '\n');
  text += "0\n0\n";
  std::ofstream out(file, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw Error(message(source, ": cannot write tetgen's input ", file.string()));
}

// How a tetgen run ended.
struct Ended {
  bool signalled = false;  // killed by a signal (Debian's tetgen aborts, SIGABRT, on every error it finds)
  int code = 0;            // the exit status, or the signal
  bool ok() const { return !signalled && code == 0; }
  std::string describe() const {
    if (!signalled) return message("tetgen exited with status ", code);
    const char* name = ::sigdescr_np(code);  // thread-safe, unlike strsignal
    return message("tetgen was killed by signal ", code, name ? message(" (", name, ")") : std::string());
  }
};

// Runs `tetgen args...` in `dir` (so file names stay short: tetgen keeps them in 1024-byte buffers), stdin from
// /dev/null, stdout and stderr both into dir/log (tetgen prints its messages on stdout, failed assertions and the
// C++ runtime's "terminate called" on stderr), and waits for it. posix_spawnp, no shell: nothing in the arguments
// is interpreted, and no fork of a process that has threads (TBB's).
Ended run_tetgen(const std::filesystem::path& dir, const std::vector<std::string>& args, const std::string& log,
                 const std::string& source) {
  posix_spawn_file_actions_t actions;
  if (const int e = ::posix_spawn_file_actions_init(&actions); e != 0)
    throw Error(message(source, ": cannot run tetgen (", std::strerror(e), ")"));
  struct Destroy {
    posix_spawn_file_actions_t* a;
    ~Destroy() { ::posix_spawn_file_actions_destroy(a); }
  } destroy{&actions};
  const std::string log_path = (dir / log).string();
  int e = ::posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  if (e == 0) e = ::posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  if (e == 0) e = ::posix_spawn_file_actions_adddup2(&actions, 1, 2);
  if (e == 0) e = ::posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
  if (e != 0) throw Error(message(source, ": cannot run tetgen (", std::strerror(e), ")"));
  std::vector<std::string> words{"tetgen"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  e = ::posix_spawnp(&pid, "tetgen", &actions, nullptr, argv.data(), environ);
  if (e == ENOENT)
    throw Error(message(source, ": tetgen is not installed (Debian's package tetgen: apt install tetgen; "
                                "scripts/deps in a source tree)"));
  if (e != 0) throw Error(message(source, ": cannot run tetgen (", std::strerror(e), ")"));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw Error(message(source, ": waiting for tetgen failed (", std::strerror(errno), ")"));
  if (WIFSIGNALED(status)) return {true, WTERMSIG(status)};
  return {false, WIFEXITED(status) ? WEXITSTATUS(status) : -1};
}

// The file's text ("" if it cannot be read), at most its last `limit` bytes (read whole: tetgen's logs are small).
std::string file_tail(const std::filesystem::path& file, std::size_t limit) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  return text.size() > limit ? text.substr(text.size() - limit) : text;
}

// The last (at most 3) non-blank lines of tetgen's log, joined by " / " and cut to 200 characters, or "no output".
std::string last_lines(const std::filesystem::path& log) {
  const std::string text = file_tail(log, 4096);
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    line = line.substr(first);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    lines.push_back(line);
  }
  if (lines.empty()) return "no output";
  std::string out;
  for (std::size_t i = lines.size() > 3 ? lines.size() - 3 : 0; i < lines.size(); ++i)
    out += (out.empty() ? "" : " / ") + lines[i];
  return out.size() > 200 ? out.substr(0, 197) + "..." : out;
}

// Whether the surface intersects itself, asked of tetgen -d (which only detects): TetGen cannot mesh such a surface,
// and Debian's tetgen then aborts without saying why (its message is lost in the unflushed stdout, or there is
// none: the C++ runtime's "terminate called after throwing an instance of 'int'", or a failed assertion). Its count
// ("Found 28 pairs of faces are intersecting") and, from the first pair's vertex triples, its two triangles; or
// nothing when it finds no intersection (or cannot run).
std::optional<std::string> intersections(const std::filesystem::path& dir, const TriangleMesh& surface,
                                         const std::string& source) {
  const Ended ended = run_tetgen(dir, {"-dz", "surface.smesh"}, "detect.log", source);
  if (!ended.ok()) return std::nullopt;
  const std::string text = file_tail(dir / "detect.log", std::numeric_limits<std::size_t>::max());  // all of it
  const auto found = text.find("Found ");
  if (found == std::string::npos || text.find(" intersecting", found) == std::string::npos) return std::nullopt;
  std::string reason = text.substr(found, text.find('\n', found) - found);
  while (!reason.empty() && (reason.back() == '\r' || reason.back() == ' ' || reason.back() == '.')) reason.pop_back();
  reason = "\"" + reason + "\"";
  // The first pair: "Facet #3 intersects facet #18 at triangles:" then "(   4,    5,    6) and (   8,   13,   12)",
  // vertices numbered from 0 (-z). Found back among the surface's triangles by their sorted corners.
  const auto pair = text.find("intersects facet");
  const auto open = pair == std::string::npos ? pair : text.find('(', pair);
  if (open != std::string::npos) {
    std::array<long long, 6> v{};
    std::size_t at = open, k = 0;
    for (; k < 6; ++k) {
      at = text.find_first_of("0123456789", at);
      if (at == std::string::npos) break;
      const auto r = std::from_chars(text.data() + at, text.data() + text.size(), v[k]);
      at = std::size_t(r.ptr - text.data());
    }
    auto triangle = [&](std::size_t first) -> std::optional<std::size_t> {
      std::array<long long, 3> key{v[first], v[first + 1], v[first + 2]};
      std::sort(key.begin(), key.end());
      for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
        std::array<long long, 3> c{surface.triangles[t][0], surface.triangles[t][1], surface.triangles[t][2]};
        std::sort(c.begin(), c.end());
        if (c == key) return t;
      }
      return std::nullopt;
    };
    if (k == 6) {
      const auto a = triangle(0), b = triangle(3);
      if (a && b) reason += message("; the first pair: triangles ", *a, " and ", *b);
    }
  }
  return message(source, ": cannot fill with tets: the surface intersects itself (tetgen -d: ", reason, ")");
}

// The mesh tetgen wrote to `stem`.node and `stem`.ele, read by load_tetgen (which keeps the corners' order: TetGen
// writes each tet positively oriented in our sense, tetgen_reader.cpp), its errors prefixed by `source`.
TetMesh read_tetgen_output(const std::filesystem::path& stem, const std::string& source) {
  try {
    return load_tetgen(stem);
  } catch (const Error& e) {
    throw Error(message(source, ": tetgen's output: ", e.what()));
  }
}

// Six times the enclosed volume; throws unless the surface is closed, manifold, outward oriented, uses every vertex,
// has finite coordinates and encloses a volume that is clearly positive against its extent.
double checked_surface(const TriangleMesh& surface, const std::string& source) {
  const std::string refused = source + ": cannot fill with tets: ";
  if (const auto defect = closed_mesh_defect(surface.triangles, surface.num_vertices()))
    throw Error(refused + *defect);
  std::vector<bool> used(std::size_t(surface.num_vertices()), false);
  for (const auto& t : surface.triangles)
    for (Index i : t) used[i] = true;
  for (Index v = 0; v < surface.num_vertices(); ++v) {
    if (!used[v])
      throw Error(message(refused, "vertex ", v, " is on no triangle (every vertex of the surface becomes one of the "
                                             "mesh's, which would leave it outside every tet)"));
    if (!surface.positions.col(v).allFinite())
      throw Error(message(refused, "vertex ", v, " has a non-finite coordinate"));
  }
  const Vec3<double> lo = surface.positions.rowwise().minCoeff(), hi = surface.positions.rowwise().maxCoeff();
  const double extent = (hi - lo).norm();
  const double six_v = six_volume<double>(surface.triangles, surface.positions);
  if (six_v < 0.0)
    throw Error(message(refused, "the surface encloses a negative volume (", six_v / 6.0,
                        " m^3): it is inside out; its triangles must wind counter-clockwise seen from outside"));
  if (!(six_v > 6.0 * parallel_sine<double>() * extent * extent * extent))
    throw Error(message(refused, "the surface is flat (volume ", six_v / 6.0, " m^3 for an extent of ", extent,
                        " m): it encloses nothing"));
  return six_v;
}

// The tetgen switches (one word) after checking the options against the enclosed volume.
std::string switches(const TetrahedralizeOptions& o, double volume, const std::string& source) {
  const std::string what = source + ": tetrahedralize: ";
  if (!std::isfinite(o.max_radius_edge_ratio) || !(o.max_radius_edge_ratio >= 1.0))
    throw Error(message(what, "max_radius_edge_ratio must be finite and >= 1 (tetgen does not finish below 1), got ",
                        o.max_radius_edge_ratio));
  if (!std::isfinite(o.max_volume) || !(o.max_volume >= 0.0))
    throw Error(message(what, "max_volume must be finite and >= 0 (0: no limit), got ", o.max_volume));
  if (o.max_volume > 0.0 && volume / o.max_volume > kMaxTets)
    throw Error(message(what, "max_volume ", o.max_volume, " m^3 would ask for more than ", kMaxTets,
                        " tets in the ", volume, " m^3 the surface encloses"));
  // -p: fill the surface (a piecewise linear complex), -q: the radius-edge bound, -a: the volume bound (-a's number
  // may have a lowercase exponent, without '+'), -M: never merge neighbouring triangles tetgen finds coplanar within
  // its tolerance (merging changed the pig's volume by 2e-7 of itself when tetgen re-triangulated the merged
  // facets), -Y: keep the surface's triangles (no vertex added on it), -z: number from 0 as we do, -Q: quiet. Not -d
  // (it only checks for intersections: run separately when tetgen fails), not -R (reversed orientation).
  // -q's number is read as digits and '.' only (an exponent would end it and start other switches): fixed notation,
  // the shortest that reads back exactly (at most 309 digits, well within tetgen's 1024-byte command line).
  std::string s = "-pq" + number_text(o.max_radius_edge_ratio, std::chars_format::fixed);
  if (o.max_volume > 0.0) {
    std::string a = number_text(o.max_volume, std::chars_format::scientific);
    a.erase(std::remove(a.begin(), a.end(), '+'), a.end());
    s += "a" + a;
  }
  s += "M";
  if (o.keep_surface) s += "Y";
  return s + "zQ";
}

// Normalised for comparing triangles as sets: rotated so that the smallest index comes first (winding kept).
std::array<Index, 3> rotated(const std::array<Index, 3>& t) {
  const int k = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
  return {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
}

// Throws unless the tets' boundary is exactly the surface's triangles, each wound as in the surface.
void check_surface_kept(const TetMesh& mesh, const TriangleMesh& surface, const std::string& source) {
  std::vector<std::array<Index, 3>> boundary = tet_mesh_surface(mesh), wanted;
  for (auto& t : boundary) t = rotated(t);
  for (const auto& t : surface.triangles) wanted.push_back(rotated(t));
  std::sort(boundary.begin(), boundary.end());
  std::vector<std::array<Index, 3>> sorted = wanted;
  std::sort(sorted.begin(), sorted.end());
  if (boundary == sorted) return;
  for (std::size_t t = 0; t < wanted.size(); ++t)
    if (!std::binary_search(boundary.begin(), boundary.end(), wanted[t]))
      throw Error(message(source, ": tetgen did not keep the surface: triangle ", t, " is not a boundary face"));
  throw Error(message(source, ": tetgen did not keep the surface: the tets have ", boundary.size(),
                      " boundary faces, the surface ", wanted.size(), " triangles"));
}

}  // namespace

TetMesh tetrahedralize(const TriangleMesh& surface, const TetrahedralizeOptions& options, const std::string& source) {
  const double six_v = checked_surface(surface, source);
  const std::string flags = switches(options, six_v / 6.0, source);
  const ScratchDir dir(source);
  write_smesh(dir.path() / "surface.smesh", surface, source);
  const Ended ended = run_tetgen(dir.path(), {flags, "surface.smesh"}, "tetgen.log", source);
  const auto node = dir.path() / "surface.1.node", ele = dir.path() / "surface.1.ele";
  if (!ended.ok() || !std::filesystem::exists(node) || !std::filesystem::exists(ele)) {
    if (const auto reason = intersections(dir.path(), surface, source)) throw Error(*reason);
    const std::string log = last_lines(dir.path() / "tetgen.log");
    if (!ended.ok()) throw Error(message(source, ": ", ended.describe(), " (tetgen ", flags, "): ", log));
    const auto missing = std::filesystem::exists(node) ? ele : node;
    throw Error(message(source, ": tetgen ", flags, " wrote no ", missing.filename().string(), ": ", log));
  }
  TetMesh mesh = read_tetgen_output(dir.path() / "surface.1", source);
  // What the header promises: the surface's vertices first, at exactly its coordinates, and the tets filling exactly
  // the volume it encloses (a surface tetgen could not mesh faithfully, e.g. one that intersects itself without
  // tetgen noticing, fails here rather than giving a wrong body).
  if (mesh.num_vertices() < surface.num_vertices())
    throw Error(message(source, ": tetgen wrote ", mesh.num_vertices(), " vertices, fewer than the surface's ",
                        surface.num_vertices()));
  for (Index v = 0; v < surface.num_vertices(); ++v)
    if (mesh.positions.col(v) != surface.positions.col(v))
      throw Error(message(source, ": tetgen moved surface vertex ", v));
  check_tet_mesh(mesh, source + ": tetgen's mesh");
  double tet_volume = 0.0;
  for (const auto& t : mesh.tets)
    tet_volume += signed_tet_volume(mesh.positions.col(t[0]), mesh.positions.col(t[1]), mesh.positions.col(t[2]),
                                    mesh.positions.col(t[3]));
  if (!(std::abs(tet_volume - six_v / 6.0) <= 1e-9 * six_v / 6.0)) {
    if (const auto reason = intersections(dir.path(), surface, source)) throw Error(*reason);
    throw Error(message(source, ": tetgen's tets fill ", tet_volume, " m^3 but the surface encloses ", six_v / 6.0,
                        " m^3"));
  }
  if (options.keep_surface) check_surface_kept(mesh, surface, source);
  return mesh;
}

}  // namespace pbd
