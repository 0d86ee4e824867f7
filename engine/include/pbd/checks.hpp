#pragma once
/// \file checks.hpp
/// The engine's input checks, exported: World's add_* and set_params calls run them, and so does pbd::io's
/// DescriptionBuilder (a scene's description, built without a world), so a bad value gives the same pbd::Error
/// message whether it comes from a scene or from an API call. Every check throws naming the call, the item and its
/// index ("add_stretch: stretch constraint 3: ...") and changes nothing; messages are built only on failure, so the
/// checks stay cheap for millions of constraints. (Contact materials and bodies: contacts.hpp; closed meshes and
/// rest volumes: closed_mesh.hpp.)
#include "pbd/constraints/traits.hpp"
#include "pbd/contacts.hpp"
#include "pbd/error.hpp"
#include "pbd/step_params.hpp"
#include "pbd/stiffness.hpp"
#include "pbd/types.hpp"

#include <cmath>
#include <array>
#include <cstddef>
#include <limits>
#include <span>
#include <string>

namespace pbd {

/// Inverse mass of a mass that passed check_mass: 0 for a pinned particle (mass = infinity), else 1 / mass.
template <class Real> Real inverse_mass_of(Real mass) { return std::isinf(mass) ? Real(0) : Real(1) / mass; }

/// Throws "<fn>: particle <index>: mass must be > 0 (or kPinned), got ..." unless mass > 0 (infinity: pinned).
template <class Real> void check_mass(Real mass, const char* fn, std::size_t index);

/// Throws unless `positions` (3×N) and `masses` (N) match in count, every position is finite and every mass passes
/// check_mass; `fn` names the call, particles are numbered from `first`.
template <class Real>
void check_particles(const Matrix3X<Real>& positions, const VectorX<Real>& masses, const char* fn, Index first);

/// Throws "<what>: stiffness k must be in [0, 1] ..." or "<what>: compliance must be finite and >= 0 ...".
void check_stiffness(const Stiffness& s, const std::string& what);

/// Throws "set_params: ..." naming the first bad step parameter (Chebyshev's included).
template <class Real> void check_params(const StepParams<Real>& p);

/// Throws "set_params: hierarchy.<field> must be in [..], got ..." naming the first bad hierarchy setting (check_params
/// runs it too, whether or not the hierarchy is enabled).
void check_hierarchy(const Hierarchy& h);

/// Largest length a collider may have in a world of `Real`, m (a plane's offset, a sphere's radius and each coordinate
/// of its centre): a contact squares distances to a sphere and adds radii and margins to them, which must stay finite,
/// so it is a sixteenth of the square root of Real's largest value (1.15e18 m in float).
template <class Real> Real max_collider_length() { return std::sqrt(std::numeric_limits<Real>::max()) / Real(16); }

/// Throws "<what>: ..." unless a plane's normal and offset are finite, the normal is not zero, the offset at most
/// max_collider_length from the origin, and its material is valid; returns |normal|.
template <class Real>
Real check_plane(const Vec3<Real>& normal, Real offset, const ContactMaterial<Real>& material, const std::string& what);

/// Throws "<what>: ..." unless a sphere's centre is finite, its radius > 0, both within max_collider_length, and its
/// material valid.
template <class Real>
void check_sphere(const Vec3<Real>& center, Real radius, const ContactMaterial<Real>& material, const std::string& what);

namespace detail {
/// "add_<name>: <noun> <index>": the item a constraint check names.
std::string constraint_item(const char* name, const char* noun, std::size_t index);
/// Throws "<item>: particle index i out of range (the world has n particles)".
[[noreturn]] void fail_particle_index(const std::string& item, Index i, std::size_t n);
/// Throws "<item>: constraint set s does not exist (n sets)".
[[noreturn]] void fail_set_index(const std::string& item, Index set, std::size_t n);
/// Throws "<item>: <what>".
[[noreturn]] void fail_constraint(const std::string& item, const std::string& what);
}  // namespace detail

/// A tearing surface (World::add_surface) on n particles: every triangle's particles exist and are distinct, every
/// cut edge's too; throws pbd::Error naming `fn` and the first bad triangle or edge.
void check_surface(std::span<const std::array<Index, 3>> triangles, std::span<const std::array<Index, 2>> cut,
                   std::size_t n, const char* fn);

/// Throws "add_<kName>: <kNoun> <index>: particle index i out of range ..." unless particle i < n.
template <class C> void check_particle_of(Index i, std::size_t n, std::size_t index) {
  if (i >= n) detail::fail_particle_index(detail::constraint_item(C::kName, C::kNoun, index), i, n);
}

/// Constraint c of built-in type C (constraint_types.hpp) as World::add<C> and DescriptionBuilder::add<C> store it,
/// the index-th of its type: its particles exist (x has one column per particle) and are distinct, its set exists
/// (among `sets`) and takes C (a set with a stress–strain curve takes only the types that take_material()), the
/// rest values not in `given` are measured in x (measure_rest), and all of them are valid
/// (rest_error). Throws pbd::Error naming the first problem, in that order.
template <class C, class X>
C checked_constraint(C c, FieldMask given, const X& x, std::span<const Stiffness> sets, std::size_t index) {
  const std::size_t n = std::size_t(x.cols());
  auto item = [&] { return detail::constraint_item(C::kName, C::kNoun, index); };
  for (Index p : c.particles) check_particle_of<C>(p, n, index);
  if (c.set >= sets.size()) detail::fail_set_index(item(), c.set, sets.size());
  if (sets[c.set].mode == StiffnessMode::material && !takes_material<C>())
    detail::fail_constraint(item(), detail::message("set ", c.set, " has a stress-strain curve, which only fibers and tet fibers take"));
  for (int a = 0; a < C::kArity; ++a)
    for (int b = a + 1; b < C::kArity; ++b)
      if (c.particles[a] == c.particles[b])
        detail::fail_constraint(item(), detail::message("names particle ", c.particles[a], " twice"));
  if (const char* undefined = measure_rest(c, x, given)) detail::fail_constraint(item(), undefined);
  if (const std::string why = rest_error(c); !why.empty()) detail::fail_constraint(item(), why);
  return c;
}

}  // namespace pbd
