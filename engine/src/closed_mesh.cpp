#include "pbd/closed_mesh.hpp"

#include "message.hpp"

#include <cstdint>
#include <unordered_map>

namespace pbd {
namespace {

std::uint64_t key(Index a, Index b) { return (std::uint64_t(a) << 32) | b; }

}  // namespace

std::optional<std::string> closed_mesh_defect(std::span<const std::array<Index, 3>> triangles, Index num_vertices) {
  if (triangles.empty()) return std::string("the mesh has no triangles");
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      if (triangles[t][k] >= num_vertices)
        return detail::message("triangle ", t, ": vertex index ", triangles[t][k], " out of range (", num_vertices,
                               " vertices)");
      if (triangles[t][k] == triangles[t][(k + 1) % 3])
        return detail::message("triangle ", t, " names vertex ", triangles[t][k], " twice");
    }
  std::unordered_map<std::uint64_t, Index> directed;
  directed.reserve(3 * triangles.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) ++directed[key(t[k], t[(k + 1) % 3])];
  auto count = [&](Index a, Index b) {
    const auto it = directed.find(key(a, b));
    return it == directed.end() ? Index(0) : it->second;
  };
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      const Index forward = count(a, b), backward = count(b, a);
      if (forward == 1 && backward == 1) continue;
      const std::string edge = detail::message("edge (", a, ", ", b, ")");
      if (forward + backward == 1) return edge + " belongs to one triangle only: the mesh is open";
      if (forward + backward > 2)
        return detail::message(edge, " is shared by ", forward + backward, " triangles: the mesh is not manifold");
      return edge + " is used twice in the same direction: the triangles are not consistently oriented";
    }
  return std::nullopt;
}

}  // namespace pbd
