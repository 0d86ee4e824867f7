#include "pbd/io/vtu_frame.hpp"

#include "base64.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/io/atomic_file.hpp"
#include "pbd/io/finite_state.hpp"
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
  else if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
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

// The faces of a body's tets, each with the index of its tet in b.tets, sorted: which tet a triangle lies on.
Lookup<std::array<Index, 3>> tet_faces(const FrameBody& b) {
  Lookup<std::array<Index, 3>> faces;
  faces.reserve(4 * b.tets.size());
  constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};  // corners, any order: keys are sorted
  for (std::size_t k = 0; k < b.tets.size(); ++k)
    for (const auto& f : kFaces)
      faces.push_back({sorted<3>({b.tets[k][f[0]], b.tets[k][f[1]], b.tets[k][f[2]]}), Index(k)});
  std::sort(faces.begin(), faces.end());
  return faces;
}

// V/V0 of a tet (signed: negative once it is turned inside out) and its Green strain |½(FᵀF − I)| (Frobenius) with
// F = Ds·Dm⁻¹, NaN without Dm⁻¹; both in double whatever Real is, the strain as violation() of its Neo-Hookean
// constraint computes it.
template <class Real>
std::pair<double, double> tet_measures(const std::array<Index, 4>& q, const FrameTetRest& rest,
                                       const PositionsView<Real>& x) {
  const Eigen::Vector3d p[4] = {detail::position_of<Real>(x, q[0]), detail::position_of<Real>(x, q[1]),
                                detail::position_of<Real>(x, q[2]), detail::position_of<Real>(x, q[3])};
  const double ratio = tet_volume<double>(p[0], p[1], p[2], p[3]) / rest.volume;
  if (!rest.inverse_rest) return {ratio, kNaN};
  Eigen::Matrix3d ds;
  ds << p[1] - p[0], p[2] - p[0], p[3] - p[0];
  const Eigen::Matrix3d F = ds * *rest.inverse_rest;
  return {ratio, 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity()).norm()};
}

// The frame's cells and their cell data (NaN where a cell has no such measure), in the order they are written.
struct FrameCells {
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
  std::vector<std::int32_t> body;  // the index of the body the cell belongs to, in topology.bodies
  std::vector<double> stretch, area, volume_ratio, strain;
  std::vector<double> fiber_strain, fiber_force;  // a fiber line's total strain and tension in N; NaN elsewhere
  std::vector<double> tet_fiber_strain, tet_fiber_stress;  // a tet's tet fiber's total strain and stress in Pa

  // Adds a cell of VTK type `type` of body `b` on world particles `corners` (the piece holds every particle in world
  // order, so a world index is a point index) with its data.
  template <std::size_t K>
  void add(const std::array<Index, K>& corners, std::int32_t b, std::uint8_t type, double s, double a, double v,
           double e) {
    for (Index p : corners) connectivity.push_back(std::int64_t(p));
    offsets.push_back(std::int64_t(connectivity.size()));
    types.push_back(type);
    body.push_back(b);
    stretch.push_back(s);
    area.push_back(a);
    volume_ratio.push_back(v);
    strain.push_back(e);
    fiber_strain.push_back(kNaN);
    fiber_force.push_back(kNaN);
    tet_fiber_strain.push_back(kNaN);
    tet_fiber_stress.push_back(kNaN);
  }
};

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
  for (const FrameBody& b : topology.bodies) {
    const Lookup<std::array<Index, 3>> tet_face = tet_faces(b);
    for (const auto& t : b.triangles) {
      for (int e = 0; e < 3; ++e) append_matches(edges, sorted<2>({t[e], t[(e + 1) % 3]}), c.stretch);
      append_matches(faces, sorted(t), c.area);
      c.stretch_begin.push_back(c.stretch.size());
      c.area_begin.push_back(c.area.size());
      const auto key = std::pair{sorted(t), Index(0)};  // the first tet with this face: the lowest index
      const auto on = std::lower_bound(tet_face.begin(), tet_face.end(), key);
      c.triangle_tet.push_back(on != tet_face.end() && on->first == key.first ? std::size_t(on->second)
                                                                               : VtuCellConstraints::kNoTet);
    }
  }
  return c;
}

namespace {

// Throws pbd::Error naming `what` unless `cells` was found for this topology and the world's constraints as they are
// now, and every line's stretch constraint is one of the world's.
template <class Real>
void check_cell_constraints(const World<Real>& world, const FrameTopology& topology, const VtuCellConstraints& cells,
                            const std::string& what) {
  const auto stretch = world.template constraints<StretchConstraint<Real>>();
  const auto area = world.template constraints<AreaConstraint<Real>>();
  std::size_t num_triangles = 0;
  for (const FrameBody& b : topology.bodies) num_triangles += b.triangles.size();
  if (cells.num_stretch != stretch.size() || cells.num_area != area.size() ||
      cells.stretch_begin.size() != num_triangles + 1 || cells.area_begin.size() != num_triangles + 1 ||
      cells.triangle_tet.size() != num_triangles)
    throw Error(message(what, ": the cell constraints were found for another world or topology (",
                        cells.num_stretch, " stretch and ", cells.num_area, " area constraints, ",
                        cells.stretch_begin.size() - 1, " triangles; now ", stretch.size(), ", ", area.size(), ", ",
                        num_triangles, ")"));
  std::size_t triangle = 0;
  for (const FrameBody& b : topology.bodies) {
    for (std::size_t k = 0; k < b.line_stretch.size(); ++k)
      if (b.line_stretch[k] >= stretch.size())
        throw Error(message(what, ": body ", b.name, ": line ", k, " draws stretch constraint ", b.line_stretch[k],
                            " but the world has ", stretch.size()));
    const std::size_t fibers = world.template constraints<FiberConstraint<Real>>().size();
    const std::size_t tet_fibers = world.template constraints<TetFiberConstraint<Real>>().size();
    for (std::size_t k = 0; k < b.tet_fiber.size(); ++k)
      if (b.tet_fiber[k] != FrameBody::kNoTetFiber && b.tet_fiber[k] >= tet_fibers)
        throw Error(message(what, ": body ", b.name, ": tet ", k, " draws tet fiber ", b.tet_fiber[k],
                            " but the world has ", tet_fibers, " (tet fibers broke since the topology was made)"));
    for (std::size_t k = 0; k < b.line_fiber.size(); ++k)
      if (b.line_fiber[k] >= fibers)
        throw Error(message(what, ": body ", b.name, ": fiber line ", k, " draws fiber ", b.line_fiber[k],
                            " but the world has ", fibers, " (fibers broke since the topology was made)"));
    for (std::size_t k = 0; k < b.triangles.size(); ++k, ++triangle) {
      const std::size_t tet = cells.triangle_tet[triangle];
      if (tet != VtuCellConstraints::kNoTet && tet >= b.tets.size())
        throw Error(message(what, ": the cell constraints were found for another topology (body ", b.name,
                            ": triangle ", k, " on tet ", tet, " of ", b.tets.size(), ")"));
    }
  }
}

// The largest violation of triangle k's constraints cs[index[i]], i in [begin[k], begin[k + 1]); NaN if it has none.
template <class Real, class View>
double largest(const View& cs, const std::vector<Index>& index, const std::vector<std::size_t>& begin, std::size_t k,
               const PositionsView<Real>& x) {
  double s = kNaN;
  for (std::size_t i = begin[k]; i < begin[k + 1]; ++i)
    s = std::isnan(s) ? violation(cs[index[i]], x) : std::max(s, violation(cs[index[i]], x));
  return s;
}

// Appends body b's cells (the index of b is `index`) with their data: its triangles (the first is triangle `triangle`
// of `cells`), its lines, its fiber lines, its tets, and for a body with none of these one vertex per particle, so
// that ParaView draws it.
template <class Real>
void add_body_cells(FrameCells& c, const World<Real>& world, const FrameBody& b, std::int32_t index,
                    const VtuCellConstraints& cells, std::size_t triangle, const std::vector<FiberReading>& fibers,
                    const std::vector<FiberReading>& tet_fibers) {
  const auto stretch = world.template constraints<StretchConstraint<Real>>();
  const auto area = world.template constraints<AreaConstraint<Real>>();
  const auto positions = world.positions();
  const PositionsView<Real> x(positions);
  std::vector<std::pair<double, double>> tet(b.tets.size());  // first: a triangle on a tet's face shows its tet's
  for (std::size_t k = 0; k < b.tets.size(); ++k) tet[k] = tet_measures<Real>(b.tets[k], b.tet_rest[k], x);
  const std::size_t before = c.types.size();
  for (const auto& t : b.triangles) {
    const double stretched = largest<Real>(stretch, cells.stretch, cells.stretch_begin, triangle, x);
    const double area_error = largest<Real>(area, cells.area, cells.area_begin, triangle, x);
    const std::size_t on = cells.triangle_tet[triangle++];
    const auto [v, e] = on == VtuCellConstraints::kNoTet ? std::pair{kNaN, kNaN} : tet[on];
    c.add(t, index, 5, stretched, area_error, v, e);  // VTK_TRIANGLE
  }
  for (std::size_t k = 0; k < b.lines.size(); ++k)
    c.add(b.lines[k], index, 3, violation(stretch[b.line_stretch[k]], x), kNaN, kNaN, kNaN);  // VTK_LINE
  const auto fiber = world.template constraints<FiberConstraint<Real>>();
  for (std::size_t k = 0; k < b.fiber_lines.size(); ++k) {  // VTK_LINE; stretch: the elastic strain
    c.add(b.fiber_lines[k], index, 3, violation(fiber[b.line_fiber[k]], x), kNaN, kNaN, kNaN);
    c.fiber_strain.back() = fibers[b.line_fiber[k]].strain;
    c.fiber_force.back() = fibers[b.line_fiber[k]].force;
  }
  for (std::size_t k = 0; k < b.tets.size(); ++k) {
    c.add(b.tets[k], index, 10, kNaN, kNaN, tet[k].first, tet[k].second);  // VTK_TETRA
    if (!b.tet_fiber.empty() && b.tet_fiber[k] != FrameBody::kNoTetFiber) {
      c.tet_fiber_strain.back() = tet_fibers[b.tet_fiber[k]].strain;
      c.tet_fiber_stress.back() = tet_fibers[b.tet_fiber[k]].force;
    }
  }
  if (c.types.size() == before)
    for (Index i = 0; i < b.num_particles; ++i)
      c.add(std::array<Index, 1>{b.first_particle + i}, index, 1, kNaN, kNaN, kNaN, kNaN);  // VTK_VERTEX
}

// Which cell arrays a frame carries: each only when the world has the constraints it measures (an array of NaN
// says nothing, and in ParaView's list of arrays suggests a measure the scene does not have).
struct FrameArrays {
  bool stretch = false;       // stretch constraints, or fibers drawn as lines (their elastic strain)
  bool area = false;          // area constraints
  bool volume_ratio = false;  // tets drawn (from Neo-Hookean, tet volume or tet fiber constraints)
  bool strain = false;        // a drawn tet with a rest shape: a Neo-Hookean constraint
  bool fibers = false;        // fiber_strain and fiber_force: fibers drawn as lines
  bool tet_fibers = false;    // tet_fiber_strain and tet_fiber_stress
};

template <class Real> FrameArrays frame_arrays(const World<Real>& world, const FrameTopology& topology) {
  auto any_body = [&](auto has) { return std::any_of(topology.bodies.begin(), topology.bodies.end(), has); };
  FrameArrays a;
  a.fibers = any_body([](const FrameBody& b) { return !b.fiber_lines.empty(); });
  a.stretch = !world.template constraints<StretchConstraint<Real>>().empty() || a.fibers;
  a.area = !world.template constraints<AreaConstraint<Real>>().empty();
  a.volume_ratio = any_body([](const FrameBody& b) { return !b.tets.empty(); });
  a.strain = any_body([](const FrameBody& b) {
    const auto shaped = [](const FrameTetRest& r) { return r.inverse_rest.has_value(); };
    return std::any_of(b.tet_rest.begin(), b.tet_rest.end(), shaped);
  });
  a.tet_fibers = any_body([](const FrameBody& b) { return !b.tet_fiber.empty(); });
  return a;
}

// The frame's one <Piece>: every particle with its point data, and `c` with the cell data `arrays` asks for.
template <class Real>
void append_piece(std::string& out, const World<Real>& world, const FrameTopology& topology, const FrameCells& c,
                  FrameArrays arrays) {
  const auto x = world.positions();
  const auto v = world.velocities();
  const auto w = world.inverse_masses();
  const Index n = world.num_particles();
  std::vector<std::uint8_t> pinned(n, 0);
  for (Index i = 0; i < n; ++i) pinned[i] = w[i] == Real(0) ? 1 : 0;
  std::vector<std::int32_t> body(n, 0);
  for (std::size_t k = 0; k < topology.bodies.size(); ++k) {
    const FrameBody& b = topology.bodies[k];
    std::fill_n(body.begin() + b.first_particle, b.num_particles, std::int32_t(k));
  }
  out += message("    <Piece NumberOfPoints=\"", n, "\" NumberOfCells=\"", c.types.size(), "\">\n");
  out += "      <PointData Scalars=\"inverse_mass\" Vectors=\"velocity\">\n";
  const std::size_t count = std::size_t(n) * 3;
  append_array(out, "        ", "body", 1, std::span<const std::int32_t>(body));
  append_array(out, "        ", "velocity", 3, std::span<const Real>(v.data(), count));
  append_array(out, "        ", "inverse_mass", 1, std::span<const Real>(w.data(), n));
  append_array(out, "        ", "pinned", 1, std::span<const std::uint8_t>(pinned));
  // ParaView colours by the Scalars array first: the first measure the frame has, else the body.
  const char* scalars = arrays.stretch ? "stretch" : arrays.area ? "area" : arrays.volume_ratio ? "volume_ratio"
                                                                                                  : "body";
  out += message("      </PointData>\n      <CellData Scalars=\"", scalars, "\">\n");
  append_array(out, "        ", "body", 1, std::span<const std::int32_t>(c.body));
  auto cell_array = [&](bool wanted, const char* name, const std::vector<double>& values) {
    if (wanted) append_array(out, "        ", name, 1, std::span<const double>(values));
  };
  cell_array(arrays.stretch, "stretch", c.stretch);
  cell_array(arrays.area, "area", c.area);
  cell_array(arrays.volume_ratio, "volume_ratio", c.volume_ratio);
  cell_array(arrays.strain, "strain", c.strain);
  cell_array(arrays.fibers, "fiber_strain", c.fiber_strain);
  cell_array(arrays.fibers, "fiber_force", c.fiber_force);
  cell_array(arrays.tet_fibers, "tet_fiber_strain", c.tet_fiber_strain);
  cell_array(arrays.tet_fibers, "tet_fiber_stress", c.tet_fiber_stress);
  out += "      </CellData>\n      <Points>\n";
  append_array(out, "        ", "positions", 3, std::span<const Real>(x.data(), count));
  out += "      </Points>\n      <Cells>\n";
  append_array(out, "        ", "connectivity", 1, std::span<const std::int64_t>(c.connectivity));
  append_array(out, "        ", "offsets", 1, std::span<const std::int64_t>(c.offsets));
  append_array(out, "        ", "types", 1, std::span<const std::uint8_t>(c.types));
  out += "      </Cells>\n    </Piece>\n";
}

// A body's name as it can stand in an XML comment: no "--" (nor a byte XML does not allow), which would end it.
std::string comment_safe(const std::string& name) {
  std::string out;
  for (char ch : name) {
    const auto u = static_cast<unsigned char>(ch);
    out += u < 0x20 || u == 0x7f || (ch == '-' && !out.empty() && out.back() == '-') ? '_' : ch;
  }
  return out;
}

}  // namespace

template <class Real>
std::string vtu_frame_at_time(const World<Real>& world, const FrameTopology& topology, const VtuCellConstraints& cells,
                              double time, const std::string& what) {
  check_frame_topology(topology, world.num_particles(), what);
  check_cell_constraints(world, topology, cells, what);
  check_finite_state(world, what);  // a frame of a state gone non-finite shows nothing; the run stops before it
  const FrameArrays arrays = frame_arrays(world, topology);
  const std::vector<FiberReading> fibers = arrays.fibers ? world.fibers() : std::vector<FiberReading>{};
  const std::vector<FiberReading> tet_fibers =
      arrays.tet_fibers ? world.template material_readings<TetFiberConstraint<Real>>() : std::vector<FiberReading>{};
  FrameCells c;
  std::size_t triangle = 0;  // the body's first triangle, numbered over all bodies as in `cells`
  for (std::size_t k = 0; k < topology.bodies.size(); ++k) {
    add_body_cells(c, world, topology.bodies[k], std::int32_t(k), cells, triangle, fibers, tet_fibers);
    triangle += topology.bodies[k].triangles.size();
  }
  std::string out = "<?xml version=\"1.0\"?>\n";
  out += message("<!-- pbd frame: t = ", time, " s, ", world.num_particles(), " particles; bodies (the body arrays):");
  for (std::size_t k = 0; k < topology.bodies.size(); ++k)
    out += message(k ? ", " : " ", k, " ", comment_safe(topology.bodies[k].name));
  out += " -->\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"";
  out += std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
  out += "\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n    <FieldData>\n";
  out += "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"binary\">";
  {
    std::string raw(16, '\0');
    const std::uint64_t bytes = 8;
    std::memcpy(raw.data(), &bytes, 8);
    std::memcpy(raw.data() + 8, &time, 8);
    detail::append_base64(out, raw);
  }
  out += "</DataArray>\n    </FieldData>\n";
  append_piece(out, world, topology, c, arrays);
  out += "  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

template <class Real>
std::string vtu_frame(const World<Real>& world, const FrameTopology& topology, const VtuCellConstraints& cells,
                      const std::string& what) {
  return vtu_frame_at_time(world, topology, cells, world.time(), what);
}

template <class Real>
void write_vtu_frame(const std::filesystem::path& file, const World<Real>& world, const FrameTopology& topology) {
  write_file_atomically(file, vtu_frame(world, topology, vtu_cell_constraints(world, topology), file.string()));
}

template VtuCellConstraints vtu_cell_constraints(const World<float>&, const FrameTopology&);
template VtuCellConstraints vtu_cell_constraints(const World<double>&, const FrameTopology&);
template std::string vtu_frame(const World<float>&, const FrameTopology&, const VtuCellConstraints&, const std::string&);
template std::string vtu_frame(const World<double>&, const FrameTopology&, const VtuCellConstraints&, const std::string&);
template std::string vtu_frame_at_time(const World<float>&, const FrameTopology&, const VtuCellConstraints&, double,
                                       const std::string&);
template std::string vtu_frame_at_time(const World<double>&, const FrameTopology&, const VtuCellConstraints&, double,
                                       const std::string&);
template void write_vtu_frame(const std::filesystem::path&, const World<float>&, const FrameTopology&);
template void write_vtu_frame(const std::filesystem::path&, const World<double>&, const FrameTopology&);

}  // namespace pbd
