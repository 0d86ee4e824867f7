#include "pbd/closed_mesh.hpp"

#include "pbd/constraints/degenerate.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <cmath>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace pbd {
namespace {

// Half-edge h = 3t + k of triangle t runs from t[k] to t[(k + 1) % 3].
Index from(std::span<const std::array<Index, 3>> tris, std::size_t h) { return tris[h / 3][h % 3]; }
Index to(std::span<const std::array<Index, 3>> tris, std::size_t h) { return tris[h / 3][(h + 1) % 3]; }

// Groups the half-edges by undirected edge: group[h] for every half-edge, and per group how many half-edges run from
// its smaller to its larger endpoint ([0]) and back ([1]). Half-edges are bucketed by their smaller endpoint (counting
// sort over the index range the mesh uses; a sort of all of them when that range is sparse) and matched by their
// larger one. Linear and hash-free for the usual mesh of consecutive particles.
struct EdgeGroups {
  std::vector<std::uint32_t> group;
  std::vector<std::array<std::uint32_t, 2>> count;
};

EdgeGroups group_edges(std::span<const std::array<Index, 3>> tris) {
  const std::size_t halves = 3 * tris.size();
  auto low = [&](std::size_t h) { return std::min(from(tris, h), to(tris, h)); };
  auto high = [&](std::size_t h) { return std::max(from(tris, h), to(tris, h)); };
  EdgeGroups g;
  g.group.resize(halves);
  auto add = [&](std::size_t h, bool same_as_previous, std::size_t previous) {
    if (same_as_previous) g.group[h] = g.group[previous];
    else {
      g.group[h] = std::uint32_t(g.count.size());
      g.count.push_back({0, 0});
    }
    ++g.count[g.group[h]][from(tris, h) < to(tris, h) ? 0 : 1];
  };
  Index lo = tris[0][0], hi = lo;
  for (const auto& t : tris)
    for (Index i : t) {
      lo = std::min(lo, i);
      hi = std::max(hi, i);
    }
  const std::size_t range = std::size_t(hi - lo) + 1;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted;  // ((low, high), half-edge), sorted
  if (range > 4 * halves + 64) {  // sparse indices: sort all half-edges by edge, ties in triangle order
    sorted.reserve(halves);
    for (std::size_t h = 0; h < halves; ++h)
      sorted.emplace_back((std::uint64_t(low(h)) << 32) | high(h), std::uint32_t(h));
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < halves; ++i)
      add(sorted[i].second, i > 0 && sorted[i].first == sorted[i - 1].first, i > 0 ? sorted[i - 1].second : 0);
    return g;
  }
  std::vector<std::uint32_t> begin(range + 2, 0);  // bucket v − lo is bucket[begin[v − lo], begin[v − lo + 1])
  for (std::size_t h = 0; h < halves; ++h) ++begin[low(h) - lo + 2];
  for (std::size_t v = 2; v < begin.size(); ++v) begin[v] += begin[v - 1];
  std::vector<std::uint32_t> bucket(halves);
  for (std::size_t h = 0; h < halves; ++h) bucket[begin[low(h) - lo + 1]++] = std::uint32_t(h);
  for (std::size_t v = 0; v < range; ++v) {
    const std::uint32_t b = begin[v], e = begin[v + 1];
    if (e - b <= 32) {  // compare with the earlier half-edges of the bucket
      for (std::uint32_t i = b; i < e; ++i) {
        std::uint32_t j = b;
        while (high(bucket[j]) != high(bucket[i])) ++j;
        add(bucket[i], j != i, bucket[j]);
      }
    } else {  // a hub: sort its bucket by the other endpoint
      sorted.clear();
      for (std::uint32_t i = b; i < e; ++i) sorted.emplace_back(high(bucket[i]), bucket[i]);
      std::sort(sorted.begin(), sorted.end());
      for (std::size_t i = 0; i < sorted.size(); ++i)
        add(sorted[i].second, i > 0 && sorted[i].first == sorted[i - 1].first, i > 0 ? sorted[i - 1].second : 0);
    }
  }
  return g;
}

}  // namespace

std::optional<std::string> closed_mesh_defect(std::span<const std::array<Index, 3>> triangles, Index num_vertices,
                                              Index first_number) {
  const std::uint64_t base = first_number;
  if (triangles.empty()) return std::string("the mesh has no triangles");
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      if (triangles[t][k] >= num_vertices)
        return detail::message("triangle ", t + base, ": vertex ", triangles[t][k] + base, " out of range (",
                               num_vertices, " vertices)");
      if (triangles[t][k] == triangles[t][(k + 1) % 3])
        return detail::message("triangle ", t + base, " names vertex ", triangles[t][k] + base, " twice");
    }
  if (3 * triangles.size() >= std::size_t(UINT32_MAX))
    return detail::message("the mesh has ", triangles.size(), " triangles, too many to check");
  const EdgeGroups g = group_edges(triangles);
  // The first bad edge in triangle order, as every directed edge (a, b) needs exactly one (b, a).
  for (std::size_t h = 0; h < g.group.size(); ++h) {
    const Index a = from(triangles, h), b = to(triangles, h);
    const auto& c = g.count[g.group[h]];
    const std::uint32_t forward = c[a < b ? 0 : 1], backward = c[a < b ? 1 : 0];
    if (forward == 1 && backward == 1) continue;
    const std::string edge = detail::message("edge (", a + base, ", ", b + base, ")");
    if (forward + backward == 1) return edge + " belongs to one triangle only: the mesh is open";
    if (forward + backward > 2)
      return detail::message(edge, " is shared by ", forward + backward, " triangles: the mesh is not manifold");
    return edge + " is used twice in the same direction: the triangles are not consistently oriented";
  }
  return std::nullopt;
}

template <class Real>
Real checked_rest_volume(std::span<const std::array<Index, 3>> triangles, const Matrix3X<Real>& x,
                         const PressureSchedule& pressure, std::optional<Real> rest, const std::string& what) {
  if (const auto defect = closed_mesh_defect(triangles, Index(x.cols()))) throw Error(what + ": " + *defect);
  if (!std::isfinite(pressure.from) || !std::isfinite(pressure.to) || !(pressure.from > 0.0) ||
      !(pressure.to > 0.0) || !std::isfinite(pressure.duration) || pressure.duration < 0.0)
    throw Error(what + ": pressure from/to must be finite and > 0, duration finite and >= 0");
  // Flat or inside-out: the enclosed volume must be clearly positive against the mesh's extent (scale-free).
  using Vec = Vec3<Real>;
  Vec lo = x.col(triangles[0][0]), hi = lo;
  for (const auto& t : triangles)
    for (Index i : t) {
      lo = lo.cwiseMin(Vec(x.col(i)));
      hi = hi.cwiseMax(Vec(x.col(i)));
    }
  const Real extent = (hi - lo).norm();
  const Real six_v = six_volume<Real>(triangles, x);
  if (!rest) {
    if (six_v < Real(0))
      throw Error(detail::message(what, ": the mesh encloses a negative volume (", six_v / Real(6),
                                  "): it is inside out; its triangles must wind counter-clockwise seen from outside"));
    if (!(six_v > Real(6) * parallel_sine<Real>() * extent * extent * extent))
      throw Error(detail::message(what, ": the mesh is flat (volume ", six_v / Real(6), " for an extent of ", extent,
                                  "): it encloses nothing to keep"));
  }
  const Real r = rest ? *rest : six_v;
  if (!std::isfinite(r) || !(r > Real(0)))
    throw Error(detail::message(what, ": rest volume must be finite and > 0, got ", r));
  return r;
}

template float checked_rest_volume(std::span<const std::array<Index, 3>>, const Matrix3X<float>&,
                                   const PressureSchedule&, std::optional<float>, const std::string&);
template double checked_rest_volume(std::span<const std::array<Index, 3>>, const Matrix3X<double>&,
                                    const PressureSchedule&, std::optional<double>, const std::string&);

}  // namespace pbd
