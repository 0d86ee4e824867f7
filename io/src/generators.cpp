#include "pbd/io/generators.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/detail/real_mass.hpp"
#include "pbd/io/description_builder.hpp"

#include <cmath>
#include <cstdint>

namespace pbd {

template <class Target> Body add_cloth(Target& world, const ClothOptions& o, std::optional<Index> stretch_set) {
  using Real = typename Target::Positions::Scalar;
  if (o.resolution < 2) throw Error(detail::message("add_cloth: resolution must be >= 2, got ", o.resolution));
  if (!(o.size > 0.0) || !std::isfinite(o.size)) throw Error(detail::message("add_cloth: size must be > 0"));
  if (!(o.mass > 0.0) || !std::isfinite(o.mass)) throw Error(detail::message("add_cloth: mass must be > 0"));
  if (stretch_set && *stretch_set >= world.constraint_sets().size())
    throw Error(detail::message("add_cloth: constraint set ", *stretch_set, " does not exist"));
  const Index n = Index(o.resolution);
  const Real m = detail::real_mass<Real>(o.mass / double(n * n), "add_cloth", world.num_particles());
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
      for (Index i = 0; i + 1 < n; ++i) add_edge(world, id(i, j), id(i + 1, j), *stretch_set);
    for (Index j = 0; j + 1 < n; ++j)
      for (Index i = 0; i < n; ++i) add_edge(world, id(i, j), id(i, j + 1), *stretch_set);
    for (Index j = 0; j + 1 < n; ++j)
      for (Index i = 0; i + 1 < n; ++i) add_edge(world, id(i, j), id(i + 1, j + 1), *stretch_set);
    if (world.constraint_sets()[*stretch_set].mode == StiffnessMode::material) world.add_surface(body.triangles);
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
  const Real m = detail::real_mass<Real>(o.mass, "add_rope", world.num_particles() + 1);
  VectorX<Real> mass = VectorX<Real>::Constant(n, m);
  for (Index i = 0; i < n; ++i) x.col(i) = (origin + dir.normalized() * (spacing * double(i))).cast<Real>();
  mass[0] = Target::kPinned;
  mass[n - 1] = detail::real_mass<Real>(o.end_mass, "add_rope", world.num_particles() + n - 1);
  Body body;
  body.first_particle = world.add_particles(x, mass);
  body.num_particles = n;
  if (stretch_set)
    for (Index i = 0; i + 1 < n; ++i)
      add_edge(world, body.first_particle + i, body.first_particle + i + 1, *stretch_set);
  return body;
}

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

template <class Target> Body add_grains(Target& world, const GrainsOptions& o) {
  using Real = typename Target::Positions::Scalar;
  for (int axis = 0; axis < 3; ++axis)
    if (o.count[axis] < 1)
      throw Error(detail::message("add_grains: count[", axis, "] must be >= 1, got ", o.count[axis]));
  // Checked one factor at a time, so the product cannot overflow before it is compared.
  const std::uint64_t max_index = std::uint64_t(Index(-1));
  const std::uint64_t nxy = std::uint64_t(o.count[0]) * std::uint64_t(o.count[1]);
  if (nxy > max_index || nxy * std::uint64_t(o.count[2]) > max_index)
    throw Error(detail::message("add_grains: ", o.count[0], " x ", o.count[1], " x ", o.count[2],
                                " particles are more than a world can index"));
  if (!(o.spacing > 0.0) || !std::isfinite(o.spacing))
    throw Error(detail::message("add_grains: spacing must be finite and > 0, got ", o.spacing));
  if (!(o.jitter >= 0.0 && o.jitter < 0.5))
    throw Error(detail::message("add_grains: jitter must be in [0, 0.5), got ", o.jitter));
  if (!(o.mass > 0.0) || !std::isfinite(o.mass))
    throw Error(detail::message("add_grains: mass must be finite and > 0, got ", o.mass));
  const Eigen::Vector3d origin(o.origin[0], o.origin[1], o.origin[2]);
  const Eigen::Vector3d velocity(o.velocity[0], o.velocity[1], o.velocity[2]);
  if (!origin.allFinite()) throw Error("add_grains: origin is not finite");
  if (!velocity.allFinite()) throw Error("add_grains: velocity is not finite");
  const Index nx = Index(o.count[0]), ny = Index(o.count[1]), nz = Index(o.count[2]);
  const Index n = nx * ny * nz;
  const double amplitude = o.jitter * o.spacing;
  std::uint64_t state = o.seed;
  // u in [−1, 1) from the top 53 bits: k·2^-52 − 1 is exact in double, so the jitter is the same everywhere.
  auto draw = [&] { return (double(splitmix64(state) >> 11) * 0x1p-52 - 1.0) * amplitude; };
  Matrix3X<Real> x(3, Eigen::Index(n));
  for (Index k = 0; k < nz; ++k)
    for (Index j = 0; j < ny; ++j)
      for (Index i = 0; i < nx; ++i) {
        const double lx = (double(i) - 0.5 * double(nx - 1)) * o.spacing;
        const double ly = (double(j) - 0.5 * double(ny - 1)) * o.spacing;
        const double lz = double(k) * o.spacing;
        const double dx = draw(), dy = draw(), dz = draw();
        x.col((Eigen::Index(k) * ny + j) * nx + i) =
            Vec3<Real>(Real(origin.x() + lx + dx), Real(origin.y() + ly + dy), Real(origin.z() + lz + dz));
      }
  Body body;
  const Real m = detail::real_mass<Real>(o.mass, "add_grains", world.num_particles());
  body.first_particle = world.add_particles(x, VectorX<Real>::Constant(Eigen::Index(n), m));
  body.num_particles = n;
  world.velocities().rightCols(Eigen::Index(n)) = velocity.cast<Real>().replicate(1, Eigen::Index(n));
  return body;
}

template Body add_cloth(World<float>&, const ClothOptions&, std::optional<Index>);
template Body add_cloth(World<double>&, const ClothOptions&, std::optional<Index>);
template Body add_rope(World<float>&, const RopeOptions&, std::optional<Index>);
template Body add_rope(World<double>&, const RopeOptions&, std::optional<Index>);
template Body add_cloth(DescriptionBuilder&, const ClothOptions&, std::optional<Index>);
template Body add_rope(DescriptionBuilder&, const RopeOptions&, std::optional<Index>);
template Body add_grains(World<float>&, const GrainsOptions&);
template Body add_grains(World<double>&, const GrainsOptions&);
template Body add_grains(DescriptionBuilder&, const GrainsOptions&);

}  // namespace pbd
