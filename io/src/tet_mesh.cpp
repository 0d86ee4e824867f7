#include "pbd/io/tet_mesh.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

namespace pbd {
namespace {

using detail::message;

// The four faces of a positively oriented tet (p0, p1, p2, p3), each wound counter-clockwise seen from outside:
// opposite p3, p2, p1 and p0 in turn.
constexpr int kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

Vec3<double> vertex(const TetMesh& m, Index v) { return m.positions.col(v); }

double longest_edge(const std::array<Vec3<double>, 4>& p) {
  double l2 = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) l2 = std::max(l2, (p[j] - p[i]).squaredNorm());
  return std::sqrt(l2);
}

}  // namespace

double signed_tet_volume(const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& p2,
                         const Vec3<double>& p3) {
  return (p1 - p0).cross(p2 - p0).dot(p3 - p0) / 6.0;
}

void check_tet_mesh(const TetMesh& mesh, const std::string& source) {
  if (mesh.tets.empty()) throw Error(message(source, ": the mesh has no tetrahedra"));
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    if (!mesh.positions.col(v).allFinite())
      throw Error(message(source, ": vertex ", v, " has a non-finite coordinate"));
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& tet = mesh.tets[t];
    for (int i = 0; i < 4; ++i) {
      if (tet[i] >= mesh.num_vertices())
        throw Error(message(source, ": tet ", t, " names vertex ", tet[i], "; the mesh has ", mesh.num_vertices()));
      for (int j = 0; j < i; ++j)
        if (tet[i] == tet[j]) throw Error(message(source, ": tet ", t, " names vertex ", tet[i], " twice"));
    }
    const std::array<Vec3<double>, 4> p{vertex(mesh, tet[0]), vertex(mesh, tet[1]), vertex(mesh, tet[2]),
                                        vertex(mesh, tet[3])};
    const double v = signed_tet_volume(p[0], p[1], p[2], p[3]);
    const double l = longest_edge(p);
    if (v < 0.0) throw Error(message(source, ": tet ", t, " is inverted (signed volume ", v, " m^3)"));
    if (!(6.0 * v > 1e-9 * l * l * l))
      throw Error(message(source, ": tet ", t, " is degenerate (volume ", v, " m^3 with a longest edge of ", l,
                          " m)"));
  }
}

std::vector<std::array<Index, 3>> tet_mesh_surface(const TetMesh& mesh) {
  // Faces are matched by their sorted corners: sort the face ids by that key, then a face whose key no neighbour in
  // the sorted order shares is on the boundary. The output keeps id order (tet, then face), not key order.
  const std::size_t n = 4 * mesh.tets.size();
  auto corners = [&](std::size_t id) {
    const auto& tet = mesh.tets[id / 4];
    const int* f = kFaces[id % 4];
    return std::array<Index, 3>{tet[f[0]], tet[f[1]], tet[f[2]]};
  };
  std::vector<std::array<Index, 3>> key(n);
  for (std::size_t id = 0; id < n; ++id) {
    key[id] = corners(id);
    std::sort(key[id].begin(), key[id].end());
  }
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return key[a] != key[b] ? key[a] < key[b] : a < b;
  });
  std::vector<std::uint8_t> boundary(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const bool same_before = i > 0 && key[order[i - 1]] == key[order[i]];
    const bool same_after = i + 1 < n && key[order[i + 1]] == key[order[i]];
    boundary[order[i]] = !same_before && !same_after;
  }
  std::vector<std::array<Index, 3>> out;
  for (std::size_t id = 0; id < n; ++id)
    if (boundary[id]) out.push_back(corners(id));
  return out;
}

TetMesh tet_box_mesh(const std::array<int, 3>& cells, const std::array<double, 3>& size) {
  for (int a = 0; a < 3; ++a) {
    if (cells[a] < 1) throw Error(message("tet box: cells[", a, "] must be >= 1, got ", cells[a]));
    if (!(size[a] > 0.0) || !std::isfinite(size[a]))
      throw Error(message("tet box: size[", a, "] must be > 0 and finite, got ", size[a]));
  }
  const std::int64_t nx = cells[0] + 1, ny = cells[1] + 1, nz = cells[2] + 1;
  if (nx * ny * nz > std::numeric_limits<Index>::max() / 8 || std::int64_t(cells[0]) * cells[1] * cells[2] > (1 << 26))
    throw Error(message("tet box: ", cells[0], " x ", cells[1], " x ", cells[2], " cells are too many"));
  TetMesh m;
  m.positions.resize(3, nx * ny * nz);
  auto id = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return Index((k * ny + j) * nx + i); };
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        m.positions.col(id(i, j, k)) = Vec3<double>(size[0] * double(i) / double(cells[0]),
                                                    size[1] * double(j) / double(cells[1]),
                                                    size[2] * double(k) / double(cells[2]));
  // Kuhn: one tet per order in which the path from corner (0,0,0) to (1,1,1) takes the three axes.
  constexpr int kAxisOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  m.tets.reserve(std::size_t(6) * cells[0] * cells[1] * cells[2]);
  for (std::int64_t k = 0; k < cells[2]; ++k)
    for (std::int64_t j = 0; j < cells[1]; ++j)
      for (std::int64_t i = 0; i < cells[0]; ++i)
        for (const auto& axes : kAxisOrders) {
          std::array<std::int64_t, 3> c{i, j, k};
          std::array<Index, 4> tet;
          tet[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[axes[s]];
            tet[s + 1] = id(c[0], c[1], c[2]);
          }
          if (signed_tet_volume(vertex(m, tet[0]), vertex(m, tet[1]), vertex(m, tet[2]), vertex(m, tet[3])) < 0.0)
            std::swap(tet[1], tet[2]);  // an odd axis order winds the other way
          m.tets.push_back(tet);
        }
  return m;
}

}  // namespace pbd
