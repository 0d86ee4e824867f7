#include "pbd/io/build_world.hpp"

#include "pbd/detail/message.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace pbd {
namespace {

template <class Real> constexpr const char* precision() { return sizeof(Real) == sizeof(float) ? "float" : "double"; }

std::string shown(const Eigen::Vector3d& v) { return detail::message("(", v[0], ", ", v[1], ", ", v[2], ")"); }

// Throws naming the first value of `d` that is finite in double but not in Real (1e300 as float), in the order
// particles (position, velocity, inverse mass), the rest values of each built-in constraint type (in the list's
// order), volumes, planes, spheres (each with its material), contact bodies (radius, material), step parameters.
template <class Real> void check_range(const WorldDescription& d) {
  auto fits = [](double v) { return std::isfinite(Real(v)); };
  auto fits3 = [](const Eigen::Vector3d& v) { return v.cast<Real>().allFinite(); };
  auto bad = [](const std::string& what, const std::string& value) {
    throw Error(detail::message("build_world<", precision<Real>(), ">: converting precision, ", what, " (", value,
                                ") is not finite in ", precision<Real>(), " (out of range)"));
  };
  for (Index i = 0; i < d.num_particles(); ++i) {
    if (!fits3(d.positions.col(i))) bad(detail::message("the position of particle ", i), shown(d.positions.col(i)));
    if (!fits3(d.velocities.col(i))) bad(detail::message("the velocity of particle ", i), shown(d.velocities.col(i)));
    // An inverse mass that rounds to 0 in Real would pin the particle, and a subnormal one lose its motion.
    const double w = d.inverse_masses[i];
    if (!fits(w) || (w > 0.0 && !(std::abs(Real(w)) >= std::numeric_limits<Real>::min())))
      bad(detail::message("the inverse mass of particle ", i), detail::message(w));
  }
  for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    const std::vector<C>& list = d.constraints<C>();
    for_each_field<C>([&](const auto& field, auto) {
      for (std::size_t i = 0; i < list.size(); ++i) {
        const auto& value = list[i].*field.member;
        if constexpr (std::is_arithmetic_v<std::decay_t<decltype(value)>>) {
          if (!fits(value)) bad(detail::message("the ", field.noun, " of ", C::kNoun, " ", i), detail::message(value));
        } else if (!fits3(value)) {
          bad(detail::message("the ", field.noun, " of ", C::kNoun, " ", i), shown(value));
        }
      }
    });
  });
  for (std::size_t i = 0; i < d.volumes.size(); ++i)
    if (!fits(d.volumes[i].rest))
      bad(detail::message("the rest volume of volume constraint ", i), detail::message(d.volumes[i].rest));
  // Restitution lies in [0, 1] and always fits; friction coefficients may be any finite value.
  auto fits_material = [&](const ContactMaterial<double>& m) {
    return fits(m.static_friction) && fits(m.kinetic_friction);
  };
  auto friction = [](const ContactMaterial<double>& m) {
    return detail::message("static ", m.static_friction, ", kinetic ", m.kinetic_friction);
  };
  for (std::size_t i = 0; i < d.planes.size(); ++i) {
    if (!fits(d.planes[i].offset)) bad(detail::message("the offset of plane ", i), detail::message(d.planes[i].offset));
    if (!fits_material(d.planes[i].material))
      bad(detail::message("the friction of plane ", i), friction(d.planes[i].material));
  }
  for (std::size_t i = 0; i < d.spheres.size(); ++i) {
    if (!fits3(d.spheres[i].center) || !fits(d.spheres[i].radius))
      bad(detail::message("sphere ", i),
          detail::message("centre ", shown(d.spheres[i].center), ", radius ", d.spheres[i].radius));
    if (!fits_material(d.spheres[i].material))
      bad(detail::message("the friction of sphere ", i), friction(d.spheres[i].material));
  }
  for (std::size_t i = 0; i < d.contact_bodies.size(); ++i) {
    const ContactBody<double>& b = d.contact_bodies[i];
    if (!fits(b.radius)) bad(detail::message("the radius of contact body ", i), detail::message(b.radius));
    if (!fits_material(b.material)) bad(detail::message("the friction of contact body ", i), friction(b.material));
  }
  const StepParams<double>& p = d.params;
  if (!fits3(p.gravity) || !fits(p.dt) || !fits(p.damping))
    bad("a step parameter (dt, gravity or damping)",
        detail::message("dt ", p.dt, ", gravity ", shown(p.gravity), ", damping ", p.damping));
}

template <class Real> ContactMaterial<Real> cast_material(const ContactMaterial<double>& m) {
  return {Real(m.static_friction), Real(m.kinetic_friction), Real(m.restitution)};
}

}  // namespace

template <class Real> World<Real> build_world(const WorldDescription& d) {
  const Index n = d.num_particles();
  if (d.velocities.cols() != n || d.inverse_masses.size() != n)
    throw Error(detail::message("build_world: ", n, " positions but ", d.velocities.cols(), " velocities and ",
                                d.inverse_masses.size(), " inverse masses"));
  check_range<Real>(d);
  World<Real> w;
  w.add_particles_by_inverse_mass(d.positions.cast<Real>(), d.inverse_masses.cast<Real>());
  w.velocities() = d.velocities.cast<Real>();
  for (const Stiffness& s : d.sets) w.add_constraint_set(s);
  for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    const std::vector<C>& list = d.constraints<C>();
    w.template reserve<rebind_t<C, Real>>(list.size());
    for (const C& c : list) w.add(convert_constraint<Real>(c));
  });
  for (const VolumeDescription& v : d.volumes) w.add_volume(v.triangles, v.set, v.pressure, Real(v.rest));
  for (const SurfaceDescription& s : d.surfaces) w.add_surface(s.triangles, s.cut);
  for (const PlaneDescription& p : d.planes)
    w.add_plane(Vec3<Real>(p.normal.cast<Real>()), Real(p.offset), cast_material<Real>(p.material));
  for (const SphereDescription& s : d.spheres)
    w.add_sphere(Vec3<Real>(s.center.cast<Real>()), Real(s.radius), cast_material<Real>(s.material));
  for (const ContactBody<double>& b : d.contact_bodies)
    w.add_contact_body({b.first, b.count, Real(b.radius), cast_material<Real>(b.material), b.self_collision, b.interior});
  const StepParams<double>& p = d.params;
  const Chebyshev<double>& c = p.chebyshev;
  w.set_params({Real(p.dt), p.substeps, p.iterations, Vec3<Real>(p.gravity.cast<Real>()), Real(p.damping),
                Real(p.collision_margin), p.solver, Real(p.jacobi_omega), p.sweep_order,
                Chebyshev<Real>{c.enabled, Real(c.rho), c.delay, Real(c.max_rho), Real(c.diverge)}, p.hierarchy});
  w.set_blocking(d.blocking);
  return w;
}

template World<float> build_world(const WorldDescription&);
template World<double> build_world(const WorldDescription&);

}  // namespace pbd
