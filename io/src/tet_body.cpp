#include "pbd/io/tet_body.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/detail/real_mass.hpp"
#include "pbd/io/description_builder.hpp"
#include "pbd/io/shape_match_clusters.hpp"

#include <algorithm>
#include <cmath>

namespace pbd {

std::vector<Index> tet_mesh_face_vertices(const TetMesh& mesh, int axis, bool max) {
  if (axis < 0 || axis > 2) throw Error(detail::message("tet_mesh_face_vertices: axis must be 0, 1 or 2, got ", axis));
  std::vector<Index> out;
  if (mesh.num_vertices() == 0) return out;
  const auto row = mesh.positions.row(axis);
  const double lo = row.minCoeff(), hi = row.maxCoeff(), tol = 1e-9 * std::max(hi - lo, 1e-300);
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    if (max ? row[v] >= hi - tol : row[v] <= lo + tol) out.push_back(v);
  return out;
}

template <class Target>
Body add_tet_body(Target& world, const TetMesh& mesh, const TetBodyOptions& o, const TetConstraintSets& sets) {
  using Real = typename Target::Positions::Scalar;
  check_tet_mesh(mesh, "add_tet_body");
  const Index n = mesh.num_vertices();
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) throw Error("add_tet_body: scale must be finite and > 0");
  if (!(o.density > 0.0) || !std::isfinite(o.density)) throw Error("add_tet_body: density must be finite and > 0");
  for (double c : o.origin)
    if (!std::isfinite(c)) throw Error("add_tet_body: origin must be finite");
  if (sets.shape_match && !(sets.beta >= 0.0 && sets.beta <= 1.0))
    throw Error(detail::message("add_tet_body: beta must be in [0, 1], got ", sets.beta));
  const std::vector<std::array<Index, 8>> clusters =
      sets.shape_match ? shape_match_clusters(mesh) : std::vector<std::array<Index, 8>>{};  // before anything is added
  if (sets.neo_hookean && (!std::isfinite(sets.ratio) || sets.ratio < 0.0))
    throw Error(detail::message("add_tet_body: ratio mu/lambda must be finite and >= 0, got ", sets.ratio));
  for (Index i : o.pinned)
    if (i >= n) throw Error(detail::message("add_tet_body: pinned vertex ", i, " out of range (", n, " vertices)"));
  if (sets.fibers) {
    const double length = std::hypot(sets.direction[0], sets.direction[1], sets.direction[2]);
    if (!(length > 0.0) || !std::isfinite(length))
      throw Error("add_tet_body: the tet fibers' direction must be finite and not zero");
  }
  // Lumped masses: a quarter of each tet's mass at each corner (scaled volumes: scale³).
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  const double s3 = o.scale * o.scale * o.scale;
  for (const auto& t : mesh.tets) {
    const double m = o.density * s3 *
        signed_tet_volume(mesh.positions.col(t[0]), mesh.positions.col(t[1]), mesh.positions.col(t[2]),
                          mesh.positions.col(t[3])) / 4.0;
    for (Index v : t) mass[v] += m;
  }
  for (Index v = 0; v < n; ++v)
    if (!(mass[v] > 0.0)) throw Error(detail::message("add_tet_body: vertex ", v, " belongs to no tet"));
  VectorX<Real> masses(n);
  for (Index v = 0; v < n; ++v)
    masses[v] = detail::real_mass<Real>(mass[v], "add_tet_body", world.num_particles() + v);
  for (Index i : o.pinned) masses[i] = Target::kPinned;
  const Eigen::Vector3d origin(o.origin[0], o.origin[1], o.origin[2]);
  const Matrix3X<Real> x = ((mesh.positions * o.scale).colwise() + origin).template cast<Real>();
  Body body;
  body.first_particle = world.add_particles(x, masses);
  body.num_particles = n;
  for (const auto& t : tet_mesh_surface(mesh))
    body.triangles.push_back({t[0] + body.first_particle, t[1] + body.first_particle, t[2] + body.first_particle});
  auto corners = [&](const std::array<Index, 4>& t) {
    return std::array<Index, 4>{t[0] + body.first_particle, t[1] + body.first_particle, t[2] + body.first_particle,
                                t[3] + body.first_particle};
  };
  if (sets.volume) {
    for (const auto& t : mesh.tets) {
      TetVolumeConstraint<Real> c = blank_constraint<TetVolumeConstraint<Real>>();
      c.particles = corners(t);
      c.set = *sets.volume;
      world.add(c, FieldMask(0));
    }
  }
  if (sets.neo_hookean) {
    for (const auto& t : mesh.tets) {
      NeoHookeanConstraint<Real> c = blank_constraint<NeoHookeanConstraint<Real>>();
      c.particles = corners(t);
      c.set = *sets.neo_hookean;
      c.ratio = Real(sets.ratio);
      world.add(c, required_fields<NeoHookeanConstraint<Real>>());
    }
  }
  if (sets.shape_match) {
    constexpr FieldMask kBeta = FieldMask(1) << 8;  // rest offsets measured, β given
    for (const auto& k : clusters) {
      ShapeMatchConstraint<Real> c = blank_constraint<ShapeMatchConstraint<Real>>();
      for (int i = 0; i < 8; ++i) c.particles[i] = k[i] + body.first_particle;
      c.set = *sets.shape_match;
      c.beta = Real(sets.beta);
      world.add(c, kBeta);
    }
  }
  if (sets.stretch) {
    std::vector<std::array<Index, 2>> edges;
    for (const auto& t : mesh.tets)
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) edges.push_back({std::min(t[i], t[j]), std::max(t[i], t[j])});
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (const auto& e : edges) add_edge(world, e[0] + body.first_particle, e[1] + body.first_particle, *sets.stretch);
  }
  if (sets.fibers) {
    constexpr FieldMask kDirection = 2u;  // V0 and b measured, ε_p 0
    for (const auto& t : mesh.tets) {
      TetFiberConstraint<Real> c = blank_constraint<TetFiberConstraint<Real>>();
      c.particles = corners(t);
      c.set = *sets.fibers;
      c.direction = Vec3<Real>(Real(sets.direction[0]), Real(sets.direction[1]), Real(sets.direction[2]));
      world.add(c, kDirection);
    }
  }
  return body;
}

template Body add_tet_body(World<float>&, const TetMesh&, const TetBodyOptions&, const TetConstraintSets&);
template Body add_tet_body(World<double>&, const TetMesh&, const TetBodyOptions&, const TetConstraintSets&);
template Body add_tet_body(DescriptionBuilder&, const TetMesh&, const TetBodyOptions&, const TetConstraintSets&);

}  // namespace pbd
