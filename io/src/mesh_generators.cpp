#include "pbd/io/mesh_generators.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace pbd {
namespace {

constexpr double kPi = 3.14159265358979323846;

TriangleMesh from_lists(const std::vector<Eigen::Vector3d>& v, std::vector<std::array<Index, 3>> t) {
  TriangleMesh m;
  m.positions.resize(3, Eigen::Index(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) m.positions.col(Eigen::Index(i)) = v[i];
  m.triangles = std::move(t);
  return m;
}

void check_positive(double value, const char* fn, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) throw Error(detail::message(fn, ": ", what, " must be finite and > 0"));
}

}  // namespace

TriangleMesh grid_mesh(int n, double size) {
  if (n < 2 || n > 4096) throw Error(detail::message("grid_mesh: resolution must be in [2, 4096], got ", n));
  check_positive(size, "grid_mesh", "size");
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<Index, 3>> t;
  const double h = size / double(n - 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) v.emplace_back(h * i, h * j, 0.0);
  auto id = [n](int i, int j) { return Index(j * n + i); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return from_lists(v, t);
}

TriangleMesh dodecahedron_mesh(double radius) {
  check_positive(radius, "dodecahedron_mesh", "radius");
  // The 20 vertices (±1, ±1, ±1), (0, ±1/φ, ±φ), (±1/φ, ±φ, 0), (±φ, 0, ±1/φ) have circumradius √3.
  const double f = (1.0 + std::sqrt(5.0)) / 2.0, g = 1.0 / f;
  std::vector<Eigen::Vector3d> v;
  for (int x : {-1, 1})
    for (int y : {-1, 1})
      for (int z : {-1, 1}) v.emplace_back(x, y, z);
  for (int a : {-1, 1})
    for (int b : {-1, 1}) {
      v.emplace_back(0, a * g, b * f);
      v.emplace_back(a * g, b * f, 0);
      v.emplace_back(a * f, 0, b * g);
    }
  // Faces: along each of the 12 face normals (0, ±φ, ±1) and its cyclic permutations, the 5 vertices with the
  // largest projection form the pentagon.
  std::vector<Eigen::Vector3d> normals;
  for (int a : {-1, 1})
    for (int b : {-1, 1}) {
      normals.emplace_back(0, a * f, b);
      normals.emplace_back(b, 0, a * f);
      normals.emplace_back(a * f, b, 0);
    }
  std::vector<std::array<Index, 3>> t;
  const std::size_t corners = v.size();
  for (const Eigen::Vector3d& n0 : normals) {
    const Eigen::Vector3d n = n0.normalized();
    double best = -1e9;
    for (std::size_t i = 0; i < corners; ++i) best = std::max(best, n.dot(v[i]));
    std::vector<Index> face;
    for (std::size_t i = 0; i < corners; ++i)
      if (n.dot(v[i]) > best - 1e-9) face.push_back(Index(i));
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (Index i : face) c += v[i];
    c /= double(face.size());
    // Order the pentagon counter-clockwise around n.
    const Eigen::Vector3d u = (v[face[0]] - c).normalized(), w = n.cross(u);
    std::sort(face.begin(), face.end(), [&](Index a, Index b) {
      return std::atan2((v[a] - c).dot(w), (v[a] - c).dot(u)) < std::atan2((v[b] - c).dot(w), (v[b] - c).dot(u));
    });
    const Index centre = Index(v.size());
    v.push_back(c);
    for (std::size_t k = 0; k < face.size(); ++k) t.push_back({centre, face[k], face[(k + 1) % face.size()]});
  }
  for (auto& p : v) p *= radius / std::sqrt(3.0);
  return from_lists(v, t);
}

TriangleMesh icosphere_mesh(int level, double radius) {
  if (level < 0 || level > 8) throw Error(detail::message("icosphere_mesh: level must be in [0, 8], got ", level));
  check_positive(radius, "icosphere_mesh", "radius");
  const double f = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, f, 0}, {1, f, 0},  {-1, -f, 0}, {1, -f, 0}, {0, -1, f},  {0, 1, f},
                                    {0, -1, -f}, {0, 1, -f}, {f, 0, -1},  {f, 0, 1},  {-f, 0, -1}, {-f, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<std::array<Index, 3>> t = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                         {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                         {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                         {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<Index, Index>, Index> mid;
    auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      const auto [it, added] = mid.emplace(key, Index(v.size()));
      if (added) v.push_back((v[a] + v[b]).normalized());
      return it->second;
    };
    std::vector<std::array<Index, 3>> next;
    next.reserve(4 * t.size());
    for (const auto& tri : t) {
      const Index a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    t.swap(next);
  }
  for (auto& p : v) p *= radius;
  return from_lists(v, t);
}

TriangleMesh tube_mesh(int segments, int rings, double radius, double length, bool capped) {
  if (segments < 3 || segments > 100000) throw Error(detail::message("tube_mesh: segments must be in [3, 100000], got ", segments));
  if (rings < 2 || rings > 100000) throw Error(detail::message("tube_mesh: rings must be in [2, 100000], got ", rings));
  check_positive(radius, "tube_mesh", "radius");
  check_positive(length, "tube_mesh", "length");
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<Index, 3>> t;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double a = 2.0 * kPi * s / segments;
      v.emplace_back(radius * std::cos(a), radius * std::sin(a), length * (double(r) / (rings - 1) - 0.5));
    }
  auto id = [segments](int r, int s) { return Index(r * segments + (s % segments)); };
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      t.push_back({id(r, s), id(r, s + 1), id(r + 1, s + 1)});
      t.push_back({id(r, s), id(r + 1, s + 1), id(r + 1, s)});
    }
  if (capped) {
    const Index bottom = Index(v.size()), top = bottom + 1;
    v.emplace_back(0, 0, -length / 2);
    v.emplace_back(0, 0, length / 2);
    for (int s = 0; s < segments; ++s) {
      t.push_back({bottom, id(0, s + 1), id(0, s)});
      t.push_back({top, id(rings - 1, s), id(rings - 1, s + 1)});
    }
  }
  return from_lists(v, t);
}

}  // namespace pbd
