#pragma once
/// \file traits.hpp
/// The words a constraint type's header declares itself with, so that every pass outside the solver (checks,
/// metrics, scenes, descriptions, Python, reports) is derived from the list in constraint_types.hpp.
///
/// A built-in fixed-arity type C<Real> declares, besides what the solver needs (kArity, kInequality, particles, set,
/// `evaluate`; see stretch.hpp):
///   kName          "stretch": reports, Python's add_<kName> and <kName>_violation (C++ adds any type with
///                  World::add<C> and removes with remove_constraints<C>)
///   kNoun          "stretch constraint": the item in error messages ("add_stretch: stretch constraint 3: ...")
///   kParticleNames the particles' argument names in Python ("a", "b")
///   kSceneKey      its key in a scene body ("stretch", "anchors"), read as kSceneForm says
///   kTiesToWorld   its constraints hold particles to fixed points (a body they hold is not free: free_bodies.cpp)
///   kMeasure       how its violation is reported: the study's error key, label, unit and scale ("stretch_pct", %)
///   kTakesMaterial optional: it may be in a set with a stress–strain curve (takes_material); such a type also
///                  has a `plastic` strain, kForceUnit (its reading's unit) and material_strain(c, x) (its total
///                  strain) and material_scale(c) (λ/h² over it is the reading) beside the functions below
///   kBreaksWithFibers optional: it leaves the model when a fiber between two of its particles breaks (a tet torn
///                  along its edge: breaks_with_fibers)
///   fields()       its rest values (members), each with its name, its noun in messages, whether a scene gives it
///                  and whether it has no default (required)
/// and three free functions found by argument-dependent lookup:
///   violation(c, x)          the normalized violation at positions x, in double (negative: not measurable)
///   measure_rest(c, x, given) fills the rest values not in `given` from positions x (a world's current ones);
///                             returns why one is undefined there, or nullptr
///   rest_error(c)            why c's rest values are invalid ("rest distance must be ..."), or "" when valid
#include "pbd/detail/message.hpp"
#include "pbd/types.hpp"
#include "pbd/violation.hpp"

#include <cstdint>
#include <tuple>
#include <type_traits>

namespace pbd {

/// How a scene makes the constraints of a type.
enum class SceneForm : std::uint8_t {
  mesh,    ///< a body's generator makes them from its mesh (edges, triangles); the key is a stiffness object
  listed,  ///< the key is {"particles": [...], <scene fields>, stiffness...}: one constraint per entry (an entry is a
           ///< local particle index, or an array of kArity of them), rest values not given measured at the start
};

/// Bit i set: rest value i of a constraint (fields() order) is given; the others are measured (measure_rest).
using FieldMask = std::uint32_t;
inline constexpr FieldMask kAllFields = ~FieldMask(0);  ///< every rest value given

/// One rest value of constraint type C: the member `member` of type T (Real, or Vec3<Real>).
template <class C, class T> struct Field {
  using type = T;           ///< the member's type
  const char* name;         ///< its name: the Python keyword and the scene key ("rest", "target", "length")
  const char* noun;         ///< what messages call it ("rest length", "target")
  T C::*member;             ///< the member
  bool in_scene = false;    ///< a scene may give it (one value for all the key's entries); else measured
  bool required = false;    ///< it has no default: measure_rest refuses a constraint that does not give it
};
template <class C, class T> Field(const char*, const char*, T C::*, bool, bool) -> Field<C, T>;
template <class C, class T> Field(const char*, const char*, T C::*, bool) -> Field<C, T>;
template <class C, class T> Field(const char*, const char*, T C::*) -> Field<C, T>;

/// Whether constraint type C holds its particles to fixed points: its kTiesToWorld; a type that does not say (a
/// user-defined one may not) does not.
template <class C> constexpr bool ties_to_world() {
  if constexpr (requires { C::kTiesToWorld; }) return C::kTiesToWorld;
  else return false;
}

/// Whether constraint type C may be in a set with a stress–strain curve (StiffnessMode::material): its
/// kTakesMaterial; a type that does not say may not (constraints/fiber.hpp and tet_fiber.hpp do).
template <class C> constexpr bool takes_material() {
  if constexpr (requires { C::kTakesMaterial; }) return C::kTakesMaterial;
  else return false;
}

/// Whether a constraint of type C breaks when a constraint of a material type (takes_material) on some of its
/// particles breaks: its kBreaksWithFibers; a type that does not say does not. A tet whose edge a fiber tore, or
/// whose own fibers tore (constraints/tet_fiber.hpp), no longer holds its corners together (World::last_breaks,
/// engine/src/tear_cells.hpp), so a body of tets reinforced by fibers tears.
template <class C> constexpr bool breaks_with_fibers() {
  if constexpr (requires { C::kBreaksWithFibers; }) return C::kBreaksWithFibers;
  else return false;
}

/// Whether Solver::block projects a block's interior of C color by color (block_layout.hpp), rather than in
/// insertion order: its kColoredInteriors; a type that does not say does not. For a type whose constraints share
/// each particle with many others (a tet's corner is in about 20 tets), insertion order is one long dependency
/// chain; colored, a block's constraints run by the type's SIMD kernel, a color at a time, on the thread that owns
/// the block. A property of the type, so the order (and the bits) never depend on the CPU.
template <class C> constexpr bool colored_interiors() {
  if constexpr (requires { C::kColoredInteriors; }) return C::kColoredInteriors;
  else return false;
}

/// Multipliers (λ values) per constraint of C: its kMultipliers (a type whose own `correction` solves several
/// coupled constraints at once, neo_hookean.hpp), else 1.
template <class C> constexpr int multipliers() {
  if constexpr (requires { C::kMultipliers; }) return C::kMultipliers;
  else return 1;
}

/// Number of rest values of C.
template <class C> inline constexpr std::size_t kNumFields = std::tuple_size_v<decltype(C::fields())>;

/// Calls f(field, i) for each rest value of C, in order (i: std::integral_constant).
template <class C, class F> constexpr void for_each_field(F&& f) {
  constexpr auto fields = C::fields();
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(std::get<I>(fields), std::integral_constant<std::size_t, I>{}), ...);
  }(std::make_index_sequence<kNumFields<C>>{});
}

/// The mask of C's rest values that have no default (Field::required): what a caller must give.
template <class C> constexpr FieldMask required_fields() {
  FieldMask mask = 0;
  for_each_field<C>([&](const auto& field, auto i) {
    if (field.required) mask |= FieldMask(1) << decltype(i)::value;
  });
  return mask;
}

/// A constraint of type C with no particles named yet (all 0), set 0 and every rest value zero (a vector's too).
template <class C> C blank_constraint() {
  C c{};
  for_each_field<C>([&](const auto& field, auto) {
    using T = typename std::decay_t<decltype(field)>::type;
    if constexpr (std::is_arithmetic_v<T>) c.*field.member = T(0);
    else c.*field.member = T::Zero();
  });
  return c;
}

/// `value` in precision To: a scalar cast, or a vector's components cast (as build_world and describe_world convert).
template <class To, class From> To convert_value(const From& value) {
  if constexpr (std::is_arithmetic_v<From>) return To(value);
  else return To(value.template cast<typename To::Scalar>());
}

/// C<Real> as C<To> (every built-in type is a template on its precision alone).
template <class C, class To> struct Rebind;
template <template <class> class T, class R, class To> struct Rebind<T<R>, To> {
  using type = T<To>;  ///< the same type in precision To
};
template <class C, class To> using rebind_t = typename Rebind<C, To>::type;  ///< C in precision To

/// Constraint c in precision To: the same particles and set, each rest value converted (convert_value).
template <class To, class C> rebind_t<C, To> convert_constraint(const C& c) {
  using D = rebind_t<C, To>;
  D out{};
  out.particles = c.particles;
  out.set = c.set;
  if constexpr (requires { c.pin; }) out.pin = c.pin;  // not a rest value: the particle a tether follows (tether.hpp)
  constexpr auto to = D::fields();
  for_each_field<C>([&](const auto& from, auto i) {
    const auto& field = std::get<decltype(i)::value>(to);
    out.*field.member = convert_value<typename std::decay_t<decltype(field)>::type>(c.*from.member);
  });
  return out;
}

}  // namespace pbd
