#include "pbd/io/describe_world.hpp"

namespace pbd {
namespace {

template <class Real> ContactMaterial<double> to_double(const ContactMaterial<Real>& m) {
  return {double(m.static_friction), double(m.kinetic_friction), double(m.restitution)};
}

}  // namespace

template <class Real> WorldDescription describe_world(const World<Real>& w) {
  WorldDescription d;
  d.positions = w.positions().template cast<double>();
  d.velocities = w.velocities().template cast<double>();
  d.inverse_masses = w.inverse_masses().template cast<double>();
  d.sets.assign(w.constraint_sets().begin(), w.constraint_sets().end());
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    const auto& constraints = w.template constraints<C>();
    auto& list = d.constraints<rebind_t<C, double>>();
    list.reserve(constraints.size());
    for (const C& c : constraints) list.push_back(convert_constraint<double>(c));
  });
  const VolumeConstraints<Real>& volumes = w.volumes();
  for (const auto& c : volumes.items)
    d.volumes.push_back({{volumes.triangles.begin() + c.triangle_begin, volumes.triangles.begin() + c.triangle_end},
                         c.set, double(c.rest), c.pressure});
  for (Index s = 0; s < w.num_surfaces(); ++s)
    d.surfaces.push_back({{w.surface(s).begin(), w.surface(s).end()}, {w.surface_cut(s).begin(), w.surface_cut(s).end()}});
  for (const auto& p : w.colliders().planes)
    d.planes.push_back({p.normal.template cast<double>(), double(p.offset), to_double(p.material)});
  for (const auto& s : w.colliders().spheres)
    d.spheres.push_back({s.center.template cast<double>(), double(s.radius), to_double(s.material)});
  for (const auto& b : w.contact_bodies())
    d.contact_bodies.push_back({b.first, b.count, double(b.radius), to_double(b.material), b.self_collision, b.interior});
  const StepParams<Real>& p = w.params();
  const Chebyshev<Real>& c = p.chebyshev;
  d.params = {double(p.dt), p.substeps, p.iterations, p.gravity.template cast<double>(), double(p.damping),
              double(p.collision_margin), p.solver, double(p.jacobi_omega), p.sweep_order,
              Chebyshev<double>{c.enabled, double(c.rho), c.delay, double(c.max_rho), double(c.diverge)}, p.hierarchy};
  d.blocking = w.blocking();
  return d;
}

template WorldDescription describe_world(const World<float>&);
template WorldDescription describe_world(const World<double>&);

}  // namespace pbd
