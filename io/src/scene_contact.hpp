#pragma once
// Scene keys of contacts (docs/scenes.md): the "friction" and "restitution" of a collider or of a body's "contact"
// object, and a body's "contact" object, which makes the body a contact body. Private to pbd::io.
#include "json_reader.hpp"
#include "pbd/constraints/contact_material.hpp"
#include "pbd/io/description_builder.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/world_description.hpp"

#include <string>
#include <utility>
#include <vector>

namespace pbd::detail {

/// Largest contact radius a scene may give, m: the largest length any scene key takes.
inline constexpr double kMaxContactRadius = 1e6;

/// The material under `o`'s optional keys "friction" and "restitution" (each absent: 0). "friction" is a number μ ≥ 0
/// (μs = μk = μ) or {"static": μs, "kinetic": μk} with at least one of the two, an omitted one taking the other's
/// value; "restitution" is in [0, 1]. Errors name the file and the key.
ContactMaterial<double> read_contact_material(const JsonObject& o);

/// The particles of `body` on none of its surface triangles (world indices, ascending): a tet body's interior, which
/// touches nothing but colliders (ContactBody::interior). A body without triangles has none.
std::vector<Index> interior_particles(const Body& body);

/// The optional "contact" object of the body object `o`: {"radius": m ≥ 0 (0), "friction", "restitution",
/// "self_collision": bool (false)}. When present, `body`'s particles become a contact body of `world`; absent,
/// nothing is added.
void read_contact_body(const JsonObject& o, const Body& body, DescriptionBuilder& world);

/// Throws pbd::Error naming `file`, the body (its path "/bodies/<b>") and the particle when a movable particle's
/// centre starts behind a collider's surface (inside a plane's half-space or a sphere) by more than a micrometre or a
/// millionth of the lengths involved (rounding). The first sub-step would push it out in one go and keep that push as
/// velocity. `bodies` are the scene's bodies in order (first particle, count); `plane_paths` and `sphere_paths` the
/// JSON path of each plane and each sphere of `d`, in the order added.
void check_starts_outside(const WorldDescription& d, const std::vector<std::pair<Index, Index>>& bodies,
                          const std::vector<std::string>& plane_paths, const std::vector<std::string>& sphere_paths,
                          const std::string& file);

}  // namespace pbd::detail
