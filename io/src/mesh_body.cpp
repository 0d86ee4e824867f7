#include "pbd/io/mesh_body.hpp"
#include "pbd/io/generators.hpp"

#include "edge_table.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/detail/real_mass.hpp"
#include "pbd/closed_mesh.hpp"
#include "pbd/io/description_builder.hpp"

#include <cmath>

namespace pbd {

namespace {

// Room for `more` constraints of type C<Real>, where the world can make it (the description builder can).
template <template <class> class C, class Target> void reserve_more(Target& w, std::size_t more) {
  using Real = typename Target::Positions::Scalar;
  if constexpr (requires { w.template reserve_more<C<Real>>(more); }) w.template reserve_more<C<Real>>(more);
}

}  // namespace

template <class Target>
void add_mesh_constraints(Target& world, std::span<const std::array<Index, 3>> triangles,
                          const MeshConstraintSets& sets) {
  using Real = typename Target::Positions::Scalar;
  const detail::EdgeTable edges = sets.stretch || sets.bending ? detail::edge_table(triangles) : detail::EdgeTable{};
  if (sets.stretch) {
    reserve_more<StretchConstraint>(world, edges.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const auto [a, b] = edges.edge(triangles, e);
      add_edge(world, a, b, *sets.stretch);
    }
    if (world.constraint_sets()[*sets.stretch].mode == StiffnessMode::material) world.add_surface(triangles);
  }
  if (sets.bending) {
    std::size_t interior = 0;
    for (std::uint8_t c : edges.count) interior += c == 2;
    reserve_more<BendingConstraint>(world, interior);
    const auto& x = world.positions();
    for (std::size_t e = 0; e < edges.size(); ++e) {
      if (edges.count[e] != 2) continue;  // bending pairs: edges of exactly two triangles, as mesh_bending_pairs
      const std::array<Index, 4> b = edges.pair(triangles, e);
      // A pair that is degenerate at rest (collinear corners) has no rest angle: it gets no bending constraint. The
      // others get the angle computed here, which is the one World would compute for them.
      const Real angle = dihedral_angle<Real>(x.col(b[0]), x.col(b[1]), x.col(b[2]), x.col(b[3]));
      if (angle < Real(0)) continue;
      world.add_bending(b[0], b[1], b[2], b[3], *sets.bending, angle);
    }
  }
  if (sets.area) {
    reserve_more<AreaConstraint>(world, triangles.size());
    for (const auto& t : triangles) world.add_area(t[0], t[1], t[2], *sets.area);
  }
  if (sets.volume) world.add_volume(triangles, *sets.volume, sets.pressure);
}

template <class Target>
Body add_mesh(Target& world, const TriangleMesh& mesh, const MeshBodyOptions& o, const MeshConstraintSets& sets) {
  using Real = typename Target::Positions::Scalar;
  const Index n = mesh.num_vertices();
  if (n == 0) throw Error("add_mesh: the mesh has no vertices");
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) throw Error("add_mesh: scale must be finite and > 0");
  if (!(o.mass > 0.0) || !std::isfinite(o.mass)) throw Error("add_mesh: mass must be finite and > 0");
  for (const auto& t : mesh.triangles)
    for (Index i : t)
      if (i >= n) throw Error(detail::message("add_mesh: vertex index ", i, " out of range (", n, " vertices)"));
  if (sets.volume)
    if (const auto defect = closed_mesh_defect(mesh.triangles, n)) throw Error("add_mesh: volume: " + *defect);
  for (Index i : o.pinned)
    if (i >= n) throw Error(detail::message("add_mesh: pinned vertex ", i, " out of range (", n, " vertices)"));
  const Eigen::Vector3d origin(o.origin[0], o.origin[1], o.origin[2]);
  Matrix3X<Real> x = ((mesh.positions * o.scale).colwise() + origin).template cast<Real>();
  const Real m = detail::real_mass<Real>(o.mass / double(n), "add_mesh", world.num_particles());
  VectorX<Real> mass = VectorX<Real>::Constant(n, m);
  for (Index i : o.pinned) mass[i] = Target::kPinned;
  Body body;
  body.first_particle = world.add_particles(x, mass);
  body.num_particles = n;
  body.triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    body.triangles.push_back({t[0] + body.first_particle, t[1] + body.first_particle, t[2] + body.first_particle});
  add_mesh_constraints(world, body.triangles, sets);
  return body;
}

template void add_mesh_constraints(World<float>&, std::span<const std::array<Index, 3>>, const MeshConstraintSets&);
template void add_mesh_constraints(World<double>&, std::span<const std::array<Index, 3>>, const MeshConstraintSets&);
template Body add_mesh(World<float>&, const TriangleMesh&, const MeshBodyOptions&, const MeshConstraintSets&);
template Body add_mesh(World<double>&, const TriangleMesh&, const MeshBodyOptions&, const MeshConstraintSets&);
template void add_mesh_constraints(DescriptionBuilder&, std::span<const std::array<Index, 3>>, const MeshConstraintSets&);
template Body add_mesh(DescriptionBuilder&, const TriangleMesh&, const MeshBodyOptions&, const MeshConstraintSets&);

}  // namespace pbd
