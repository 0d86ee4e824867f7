#include "pbd/io/generators.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/io/description_builder.hpp"

#include <cmath>

namespace pbd {

template <class Target> Body add_cloth(Target& world, const ClothOptions& o, std::optional<Index> stretch_set) {
  using Real = typename Target::Positions::Scalar;
  if (o.resolution < 2) throw Error(detail::message("add_cloth: resolution must be >= 2, got ", o.resolution));
  if (!(o.size > 0.0) || !std::isfinite(o.size)) throw Error(detail::message("add_cloth: size must be > 0"));
  if (!(o.mass > 0.0) || !std::isfinite(o.mass)) throw Error(detail::message("add_cloth: mass must be > 0"));
  if (stretch_set && *stretch_set >= world.constraint_sets().size())
    throw Error(detail::message("add_cloth: constraint set ", *stretch_set, " does not exist"));
  const Index n = Index(o.resolution);
  const Real m = Real(o.mass / double(n * n));
  const Real spacing = Real(o.size / double(n - 1));
  Matrix3X<Real> x(3, Eigen::Index(n) * n);
  VectorX<Real> mass = VectorX<Real>::Constant(Eigen::Index(n) * n, m);
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i)
      x.col(j * n + i) = Vec3<Real>(Real(o.origin[0]) + spacing * Real(i), Real(o.origin[1]) + spacing * Real(j),
                                    Real(o.origin[2]));
  if (o.pin == ClothPin::corners) {
    mass[(n - 1) * n] = Target::kPinned;
    mass[(n - 1) * n + n - 1] = Target::kPinned;
  } else if (o.pin == ClothPin::edge) {
    for (Index i = 0; i < n; ++i) mass[(n - 1) * n + i] = Target::kPinned;
  }
  Body body;
  body.first_particle = world.add_particles(x, mass);
  body.num_particles = n * n;
  const Index f = body.first_particle;
  auto id = [&](Index i, Index j) { return f + j * n + i; };
  for (Index j = 0; j + 1 < n; ++j)
    for (Index i = 0; i + 1 < n; ++i) {
      body.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      body.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  if (stretch_set) {
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i + 1 < n; ++i) world.add_stretch(id(i, j), id(i + 1, j), *stretch_set);
    for (Index j = 0; j + 1 < n; ++j)
      for (Index i = 0; i < n; ++i) world.add_stretch(id(i, j), id(i, j + 1), *stretch_set);
    for (Index j = 0; j + 1 < n; ++j)
      for (Index i = 0; i + 1 < n; ++i) world.add_stretch(id(i, j), id(i + 1, j + 1), *stretch_set);
  }
  return body;
}

template <class Target> Body add_rope(Target& world, const RopeOptions& o, std::optional<Index> stretch_set) {
  using Real = typename Target::Positions::Scalar;
  if (o.particles < 2) throw Error(detail::message("add_rope: particles must be >= 2, got ", o.particles));
  if (!(o.length > 0.0) || !std::isfinite(o.length)) throw Error("add_rope: length must be > 0");
  if (!(o.mass > 0.0) || !std::isfinite(o.mass)) throw Error("add_rope: mass must be > 0");
  if (!(o.end_mass > 0.0) || !std::isfinite(o.end_mass)) throw Error("add_rope: end_mass must be > 0");
  if (stretch_set && *stretch_set >= world.constraint_sets().size())
    throw Error(detail::message("add_rope: constraint set ", *stretch_set, " does not exist"));
  const Eigen::Vector3d dir(o.direction[0], o.direction[1], o.direction[2]);
  if (!(dir.norm() > 0.0) || !dir.allFinite()) throw Error("add_rope: direction must be non-zero and finite");
  const Eigen::Vector3d origin(o.origin[0], o.origin[1], o.origin[2]);
  const Index n = Index(o.particles);
  const double spacing = o.length / double(n - 1);
  Matrix3X<Real> x(3, n);
  VectorX<Real> mass = VectorX<Real>::Constant(n, Real(o.mass));
  for (Index i = 0; i < n; ++i) x.col(i) = (origin + dir.normalized() * (spacing * double(i))).cast<Real>();
  mass[0] = Target::kPinned;
  mass[n - 1] = Real(o.end_mass);
  Body body;
  body.first_particle = world.add_particles(x, mass);
  body.num_particles = n;
  if (stretch_set)
    for (Index i = 0; i + 1 < n; ++i)
      world.add_stretch(body.first_particle + i, body.first_particle + i + 1, *stretch_set);
  return body;
}

template Body add_cloth(World<float>&, const ClothOptions&, std::optional<Index>);
template Body add_cloth(World<double>&, const ClothOptions&, std::optional<Index>);
template Body add_rope(World<float>&, const RopeOptions&, std::optional<Index>);
template Body add_rope(World<double>&, const RopeOptions&, std::optional<Index>);
template Body add_cloth(DescriptionBuilder&, const ClothOptions&, std::optional<Index>);
template Body add_rope(DescriptionBuilder&, const RopeOptions&, std::optional<Index>);

}  // namespace pbd
