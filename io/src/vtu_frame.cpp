#include "pbd/io/vtu_frame.hpp"

#include "base64.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/io/atomic_file.hpp"
#include "pbd/metrics.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <utility>

namespace pbd {
namespace {

using detail::message;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The VTK type name of a value type.
template <class T> constexpr const char* vtk_type() {
  if constexpr (std::is_same_v<T, float>) return "Float32";
  else if constexpr (std::is_same_v<T, double>) return "Float64";
  else if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  else if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
  else static_assert(sizeof(T) == 0, "no VTK type");
}

// A <DataArray> of `values` (`components` per tuple), inline base64 binary: a UInt64 byte count, then the bytes,
// encoded together.
template <class T>
void append_array(std::string& out, const char* indent, const char* name, int components, std::span<const T> values) {
  out += indent;
  out += "<DataArray type=\"";
  out += vtk_type<T>();
  out += '"';
  if (name) out += message(" Name=\"", name, "\"");
  if (components > 1) out += message(" NumberOfComponents=\"", components, "\"");
  out += " format=\"binary\">";
  const std::uint64_t bytes = values.size() * sizeof(T);
  std::string raw(sizeof bytes + bytes, '\0');
  std::memcpy(raw.data(), &bytes, sizeof bytes);
  if (bytes) std::memcpy(raw.data() + sizeof bytes, values.data(), bytes);
  detail::append_base64(out, raw);
  out += "</DataArray>\n";
}

// Sorted (key, constraint) pairs for lookups of the constraints on an edge or a triangle.
template <class Key> using Lookup = std::vector<std::pair<Key, Index>>;

template <std::size_t K> std::array<Index, K> sorted(std::array<Index, K> a) {
  std::sort(a.begin(), a.end());
  return a;
}

// Appends to `out` every constraint of `lookup` whose key is `key`.
template <class Key> void append_matches(const Lookup<Key>& lookup, const Key& key, std::vector<Index>& out) {
  auto it = std::lower_bound(lookup.begin(), lookup.end(), std::pair<Key, Index>{key, 0});
  for (; it != lookup.end() && it->first == key; ++it) out.push_back(it->second);
}

}  // namespace

template <class Real> VtuCellConstraints vtu_cell_constraints(const World<Real>& world, const FrameTopology& topology) {
  const auto stretch = world.template constraints<StretchConstraint<Real>>();
  const auto area = world.template constraints<AreaConstraint<Real>>();
  Lookup<std::array<Index, 2>> edges;
  edges.reserve(stretch.size());
  for (std::size_t k = 0; k < stretch.size(); ++k) edges.push_back({sorted(stretch[k].particles), Index(k)});
  std::sort(edges.begin(), edges.end());
  Lookup<std::array<Index, 3>> faces;
  faces.reserve(area.size());
  for (std::size_t k = 0; k < area.size(); ++k) faces.push_back({sorted(area[k].particles), Index(k)});
  std::sort(faces.begin(), faces.end());
  VtuCellConstraints c;
  c.num_stretch = stretch.size();
  c.num_area = area.size();
  c.stretch_begin.push_back(0);
  c.area_begin.push_back(0);
  for (const FrameBody& b : topology.bodies)
    for (const auto& t : b.triangles) {
      for (int e = 0; e < 3; ++e) append_matches(edges, sorted<2>({t[e], t[(e + 1) % 3]}), c.stretch);
      append_matches(faces, sorted(t), c.area);
      c.stretch_begin.push_back(c.stretch.size());
      c.area_begin.push_back(c.area.size());
    }
  return c;
}

template <class Real>
std::string vtu_frame(const World<Real>& world, const FrameTopology& topology, const VtuCellConstraints& cells,
                      const std::string& what) {
  check_frame_topology(topology, world.num_particles(), what);
  const auto stretch = world.template constraints<StretchConstraint<Real>>();
  const auto area = world.template constraints<AreaConstraint<Real>>();
  std::size_t num_triangles = 0;
  for (const FrameBody& b : topology.bodies) num_triangles += b.triangles.size();
  if (cells.num_stretch != stretch.size() || cells.num_area != area.size() ||
      cells.stretch_begin.size() != num_triangles + 1 || cells.area_begin.size() != num_triangles + 1)
    throw Error(message(what, ": the cell constraints were found for another world or topology (",
                        cells.num_stretch, " stretch and ", cells.num_area, " area constraints, ",
                        cells.stretch_begin.size() - 1, " triangles; now ", stretch.size(), ", ", area.size(), ", ",
                        num_triangles, ")"));
  for (const FrameBody& b : topology.bodies)
    for (std::size_t k = 0; k < b.line_stretch.size(); ++k)
      if (b.line_stretch[k] >= stretch.size())
        throw Error(message(what, ": body ", b.name, ": line ", k, " draws stretch constraint ", b.line_stretch[k],
                            " but the world has ", stretch.size()));
  const auto x = world.positions();
  const auto v = world.velocities();
  const auto w = world.inverse_masses();
  const PositionsView<Real> positions(x);

  std::string out = "<?xml version=\"1.0\"?>\n";
  out += message("<!-- pbd frame: t = ", world.time(), " s, ", world.num_particles(), " particles; bodies: ",
                 topology.bodies.size(), " -->\n");
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"";
  out += std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
  out += "\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n    <FieldData>\n";
  const double time = world.time();
  out += "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"binary\">";
  {
    std::string raw(16, '\0');
    const std::uint64_t bytes = 8;
    std::memcpy(raw.data(), &bytes, 8);
    std::memcpy(raw.data() + 8, &time, 8);
    detail::append_base64(out, raw);
  }
  out += "</DataArray>\n    </FieldData>\n";

  std::size_t triangle = 0;  // over all bodies, as in `cells`
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types, pinned;
  std::vector<double> cell_stretch, cell_area;
  for (const FrameBody& b : topology.bodies) {
    const Index first = b.first_particle, n = b.num_particles;
    connectivity.clear();
    offsets.clear();
    types.clear();
    cell_stretch.clear();
    cell_area.clear();
    for (const auto& t : b.triangles) {
      for (Index p : t) connectivity.push_back(std::int64_t(p - first));
      offsets.push_back(std::int64_t(connectivity.size()));
      types.push_back(5);  // VTK_TRIANGLE
      double s = kNaN, a = kNaN;
      for (std::size_t k = cells.stretch_begin[triangle]; k < cells.stretch_begin[triangle + 1]; ++k)
        s = std::isnan(s) ? violation(stretch[cells.stretch[k]], positions)
                          : std::max(s, violation(stretch[cells.stretch[k]], positions));
      for (std::size_t k = cells.area_begin[triangle]; k < cells.area_begin[triangle + 1]; ++k)
        a = std::isnan(a) ? violation(area[cells.area[k]], positions)
                          : std::max(a, violation(area[cells.area[k]], positions));
      cell_stretch.push_back(s);
      cell_area.push_back(a);
      ++triangle;
    }
    for (std::size_t k = 0; k < b.lines.size(); ++k) {
      for (Index p : b.lines[k]) connectivity.push_back(std::int64_t(p - first));
      offsets.push_back(std::int64_t(connectivity.size()));
      types.push_back(3);  // VTK_LINE
      cell_stretch.push_back(violation(stretch[b.line_stretch[k]], positions));
      cell_area.push_back(kNaN);
    }
    if (b.triangles.empty() && b.lines.empty())
      for (Index i = 0; i < n; ++i) {
        connectivity.push_back(std::int64_t(i));
        offsets.push_back(std::int64_t(connectivity.size()));
        types.push_back(1);  // VTK_VERTEX
        cell_stretch.push_back(kNaN);
        cell_area.push_back(kNaN);
      }
    pinned.assign(n, 0);
    for (Index i = 0; i < n; ++i) pinned[i] = w[first + i] == Real(0) ? 1 : 0;

    out += message("    <Piece NumberOfPoints=\"", n, "\" NumberOfCells=\"", types.size(), "\">\n");
    out += "      <PointData Scalars=\"inverse_mass\" Vectors=\"velocity\">\n";
    const std::size_t from = std::size_t(first) * 3, count = std::size_t(n) * 3;
    append_array(out, "        ", "velocity", 3, std::span<const Real>(v.data() + from, count));
    append_array(out, "        ", "inverse_mass", 1, std::span<const Real>(w.data() + first, n));
    append_array(out, "        ", "pinned", 1, std::span<const std::uint8_t>(pinned));
    out += "      </PointData>\n      <CellData Scalars=\"stretch\">\n";
    append_array(out, "        ", "stretch", 1, std::span<const double>(cell_stretch));
    append_array(out, "        ", "area", 1, std::span<const double>(cell_area));
    out += "      </CellData>\n      <Points>\n";
    append_array(out, "        ", "positions", 3, std::span<const Real>(x.data() + from, count));
    out += "      </Points>\n      <Cells>\n";
    append_array(out, "        ", "connectivity", 1, std::span<const std::int64_t>(connectivity));
    append_array(out, "        ", "offsets", 1, std::span<const std::int64_t>(offsets));
    append_array(out, "        ", "types", 1, std::span<const std::uint8_t>(types));
    out += "      </Cells>\n    </Piece>\n";
  }
  out += "  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

template <class Real>
void write_vtu_frame(const std::filesystem::path& file, const World<Real>& world, const FrameTopology& topology) {
  write_file_atomically(file, vtu_frame(world, topology, vtu_cell_constraints(world, topology), file.string()));
}

template VtuCellConstraints vtu_cell_constraints(const World<float>&, const FrameTopology&);
template VtuCellConstraints vtu_cell_constraints(const World<double>&, const FrameTopology&);
template std::string vtu_frame(const World<float>&, const FrameTopology&, const VtuCellConstraints&, const std::string&);
template std::string vtu_frame(const World<double>&, const FrameTopology&, const VtuCellConstraints&, const std::string&);
template void write_vtu_frame(const std::filesystem::path&, const World<float>&, const FrameTopology&);
template void write_vtu_frame(const std::filesystem::path&, const World<double>&, const FrameTopology&);

}  // namespace pbd
