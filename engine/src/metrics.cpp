#include "pbd/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace pbd {
namespace {

using Accumulator = ViolationAccumulator;
using detail::relative_error;

}  // namespace

template <class Real> Violation penetration(const World<Real>& world) {
  const auto x = world.positions();
  const auto w = world.inverse_masses();
  std::vector<double> radius(world.num_particles(), 0.0);  // a particle of a contact body keeps r from the surface
  for (const auto& b : world.contact_bodies())
    for (Index i = b.first; i < b.first + b.count; ++i) radius[i] = double(b.radius);
  Accumulator acc;
  for (Index i = 0; i < world.num_particles(); ++i) {
    if (w[i] == Real(0)) continue;
    const Eigen::Vector3d p = x.col(i).template cast<double>();
    for (const auto& pl : world.colliders().planes)
      acc.add(std::max(0.0, double(pl.offset) + radius[i] - pl.normal.template cast<double>().dot(p)));
    for (const auto& s : world.colliders().spheres)
      acc.add(std::max(0.0, double(s.radius) + radius[i] - (p - s.center.template cast<double>()).norm()));
  }
  return acc.result();
}

template <class Real> Violation particle_overlap(const World<Real>& world) {
  const auto x = world.positions();
  Accumulator acc;
  for (const auto& c : world.last_particle_contacts()) {
    const double d = (x.col(c.particles[0]) - x.col(c.particles[1])).template cast<double>().norm();
    acc.add(std::max(0.0, 1.0 - d / double(c.distance)));
  }
  return acc.result();
}

template <class Real> Violation volume_violation(const World<Real>& world) {
  const auto& v = world.volumes();
  Accumulator acc;
  if (v.empty()) return acc.result();
  const Matrix3X<double> x = world.positions().template cast<double>();
  for (const auto& c : v.items) {
    const std::span<const std::array<Index, 3>> tris(v.triangles.data() + c.triangle_begin,
                                                     c.triangle_end - c.triangle_begin);
    acc.add(relative_error(six_volume<double>(tris, x), double(c.rest) * c.pressure.at(world.time())));
  }
  return acc.result();
}

template <class Real> std::vector<NamedViolation> constraint_violations(const World<Real>& world) {
  std::vector<NamedViolation> out;
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    if (world.template constraints<C>().empty()) return;
    out.push_back({C::kName, violation_of<C>(world), C::kMeasure});
  });
  if (!world.volumes().empty())
    out.push_back({VolumeConstraint<Real>::kName, volume_violation(world), VolumeConstraint<Real>::kMeasure});
  if (!world.colliders().empty())
    out.push_back({CollisionConstraint<Real>::kName, penetration(world), CollisionConstraint<Real>::kMeasure});
  bool radii = false;
  for (const auto& b : world.contact_bodies()) radii = radii || b.radius > Real(0);
  if (radii) out.push_back({ParticleContact<Real>::kName, particle_overlap(world), ParticleContact<Real>::kMeasure});
  return out;
}

std::vector<NamedMeasure> violation_measures() {
  std::vector<NamedMeasure> out;
  for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    out.push_back({C::kName, C::kMeasure});
  });
  out.push_back({VolumeConstraint<double>::kName, VolumeConstraint<double>::kMeasure});
  out.push_back({CollisionConstraint<double>::kName, CollisionConstraint<double>::kMeasure});
  out.push_back({ParticleContact<double>::kName, ParticleContact<double>::kMeasure});
  return out;
}

const Measure* find_measure(const std::string& type) {
  static const std::vector<NamedMeasure> all = violation_measures();
  for (const NamedMeasure& m : all)
    if (m.type == type) return &m.measure;
  return nullptr;
}

Violation pooled(const std::vector<NamedViolation>& v) {
  Accumulator acc;
  for (const auto& t : v) acc.add(t.value);
  return acc.result();
}

template <class Real> Energy energy(const World<Real>& world) {
  const auto x = world.positions();
  const auto v = world.velocities();
  const auto w = world.inverse_masses();
  const Eigen::Vector3d g = world.params().gravity.template cast<double>();
  Energy e;
  for (Index i = 0; i < world.num_particles(); ++i) {
    if (w[i] == Real(0)) continue;
    const double m = 1.0 / double(w[i]);
    e.kinetic += 0.5 * m * v.col(i).template cast<double>().squaredNorm();
    e.potential -= m * g.dot(x.col(i).template cast<double>());
  }
  return e;
}

template <class Real> double movable_mass(const World<Real>& world) {
  const auto w = world.inverse_masses();
  double m = 0.0;
  for (Eigen::Index i = 0; i < w.size(); ++i)
    if (w[i] != Real(0)) m += 1.0 / double(w[i]);
  return m;
}

template <class Real> Violation position_distance(const World<Real>& world, const Matrix3X<double>& ref) {
  if (ref.cols() != Eigen::Index(world.num_particles()))
    throw Error("position_distance: the reference has " + std::to_string(ref.cols()) + " particles, the world " +
                std::to_string(world.num_particles()));
  const auto x = world.positions();
  Accumulator acc;
  for (Eigen::Index i = 0; i < ref.cols(); ++i) acc.add((x.col(i).template cast<double>() - ref.col(i)).norm());
  return acc.result();
}

template <class Real> double bounding_diagonal(const World<Real>& world) {
  if (world.num_particles() == 0) return 0.0;
  const Matrix3X<double> x = world.positions().template cast<double>();
  return (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).norm();
}

template <class Real> std::uint64_t position_hash(const World<Real>& world) {
  const auto x = world.positions();
  const auto* bytes = reinterpret_cast<const unsigned char*>(x.data());
  std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a offset basis
  for (std::size_t k = 0; k < std::size_t(x.size()) * sizeof(Real); ++k) {
    h ^= bytes[k];
    h *= 0x100000001b3ull;  // FNV prime
  }
  return h;
}

#define PBD_METRICS_INSTANTIATE(Real)                                                             \
  template Violation penetration(const World<Real>&);                                             \
  template Violation particle_overlap(const World<Real>&);                                             \
  template Violation volume_violation(const World<Real>&);                                        \
  template std::vector<NamedViolation> constraint_violations(const World<Real>&);                 \
  template Energy energy(const World<Real>&);                                                     \
  template double movable_mass(const World<Real>&);                                               \
  template Violation position_distance(const World<Real>&, const Matrix3X<double>&);              \
  template double bounding_diagonal(const World<Real>&);                                          \
  template std::uint64_t position_hash(const World<Real>&);
PBD_METRICS_INSTANTIATE(float)
PBD_METRICS_INSTANTIATE(double)
#undef PBD_METRICS_INSTANTIATE

}  // namespace pbd
