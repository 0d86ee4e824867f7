#pragma once
// The last steps every tet mesh reader shares: keeping the nodes the tets use, and the check that names where in the
// file a refused tet was written (private to pbd::io).
#include "pbd/io/tet_mesh.hpp"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace pbd::detail {

/// The mesh of `tets`, whose corners index the nodes with coordinates xyz[3i], xyz[3i + 1], xyz[3i + 2]: only the
/// nodes some tet names are kept, in their order in `xyz`, and the tets are renumbered to them (a node no tet names
/// would be a free particle). Every corner must be a node of `xyz`.
TetMesh keep_used_nodes(const std::vector<double>& xyz, const std::vector<std::array<Index, 4>>& tets);

/// check_tet_mesh(mesh, source); when it refuses a tet, the message goes on with origin(t) for that tet t (e.g.
/// "element 12 at line 40"), so that the file can be fixed where it is wrong. Every position must be finite (the
/// readers check each coordinate as they read it): then a refusal is always about one tet.
void check_read_tet_mesh(const TetMesh& mesh, const std::string& source,
                         const std::function<std::string(std::size_t)>& origin);

}  // namespace pbd::detail
