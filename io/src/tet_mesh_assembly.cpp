#include "tet_mesh_assembly.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <limits>

namespace pbd::detail {

TetMesh keep_used_nodes(const std::vector<double>& xyz, const std::vector<std::array<Index, 4>>& tets) {
  constexpr Index kUnused = std::numeric_limits<Index>::max();
  std::vector<Index> renumbered(xyz.size() / 3, kUnused);
  for (const auto& tet : tets)
    for (const Index v : tet) renumbered[v] = 0;
  Index used = 0;
  for (Index& r : renumbered)
    if (r != kUnused) r = used++;
  TetMesh mesh;
  mesh.positions.resize(3, used);
  for (std::size_t v = 0; v < renumbered.size(); ++v)
    if (renumbered[v] != kUnused)
      for (int d = 0; d < 3; ++d) mesh.positions(d, renumbered[v]) = xyz[3 * v + std::size_t(d)];
  mesh.tets.reserve(tets.size());
  for (const auto& tet : tets)
    mesh.tets.push_back({renumbered[tet[0]], renumbered[tet[1]], renumbered[tet[2]], renumbered[tet[3]]});
  return mesh;
}

namespace {

// The first tet check_tet_mesh refuses when it is alone: the one check_tet_mesh names in the whole mesh, as what it
// checks of a tet depends on that tet only (with finite positions and at least one tet). Runs only once a mesh is
// refused, so one small mesh per tet costs nothing that matters.
std::size_t first_refused_tet(const TetMesh& mesh) {
  TetMesh one;
  one.positions.resize(3, 4);
  one.tets = {{0, 1, 2, 3}};
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    for (int k = 0; k < 4; ++k) {
      if (mesh.tets[t][k] >= mesh.num_vertices()) return t;
      one.positions.col(k) = mesh.positions.col(mesh.tets[t][k]);
    }
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < k; ++j)
        if (mesh.tets[t][k] == mesh.tets[t][j]) return t;
    try {
      check_tet_mesh(one, "");
    } catch (const Error&) {
      return t;
    }
  }
  return mesh.tets.size();
}

}  // namespace

void check_read_tet_mesh(const TetMesh& mesh, const std::string& source,
                         const std::function<std::string(std::size_t)>& origin) {
  try {
    check_tet_mesh(mesh, source);
  } catch (const Error& e) {
    const std::size_t t = first_refused_tet(mesh);
    if (t == mesh.tets.size()) throw;
    throw Error(message(e.what(), "; it is ", origin(t)));
  }
}

}  // namespace pbd::detail
