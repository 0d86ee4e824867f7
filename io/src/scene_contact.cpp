#include "scene_contact.hpp"

#include "pbd/detail/message.hpp"

#include <cmath>

namespace pbd::detail {

ContactMaterial<double> read_contact_material(const JsonObject& o) {
  ContactMaterial<double> m;
  if (o.has("friction")) {
    const nlohmann::json& f = o.value("friction");
    if (f.is_number()) {
      m.static_friction = m.kinetic_friction = o.number("friction", 0.0, kInf);
    } else if (f.is_object()) {
      const JsonObject fo = o.object("friction");
      const bool has_static = fo.has("static"), has_kinetic = fo.has("kinetic");
      if (!has_static && !has_kinetic)
        o.fail("friction", "give \"static\", \"kinetic\" or both (or one number for both)");
      // An omitted coefficient takes the other's value: {"static": μ} and {"kinetic": μ} both mean μs = μk = μ.
      if (has_static) m.static_friction = fo.number("static", 0.0, kInf);
      if (has_kinetic) m.kinetic_friction = fo.number("kinetic", 0.0, kInf);
      if (!has_static) m.static_friction = m.kinetic_friction;
      if (!has_kinetic) m.kinetic_friction = m.static_friction;
      fo.reject_unknown_keys();
    } else {
      o.fail("friction", message("expected a number or an object {\"static\": ..., \"kinetic\": ...}, got ",
                                 describe(f)));
    }
  }
  m.restitution = o.number("restitution", 0.0, 1.0, 0.0);
  return m;
}

std::vector<Index> interior_particles(const Body& body) {
  if (body.triangles.empty()) return {};  // a rope, a grain: every particle is on its outside
  std::vector<std::uint8_t> on_surface(body.num_particles, 0);
  for (const auto& t : body.triangles)
    for (Index i : t) on_surface[i - body.first_particle] = 1;
  std::vector<Index> out;
  for (Index k = 0; k < body.num_particles; ++k)
    if (!on_surface[k]) out.push_back(body.first_particle + k);
  return out;
}

void read_contact_body(const JsonObject& o, const Body& body, DescriptionBuilder& world) {
  if (!o.has("contact")) return;
  const JsonObject c = o.object("contact");
  ContactBody<double> b;
  b.first = body.first_particle;  // exactly the body's particles: a scene body is one contiguous run
  b.count = body.num_particles;
  b.radius = c.number("radius", 0.0, kMaxContactRadius, 0.0);
  b.material = read_contact_material(c);
  b.self_collision = c.boolean("self_collision", false);
  if (b.self_collision && !(b.radius > 0.0))  // points of one body cannot touch: docs/scenes.md calls it invalid
    c.fail("self_collision", "needs a \"radius\" > 0 (at least half the rest edge): points never touch one another");
  b.interior = interior_particles(body);
  c.reject_unknown_keys();
  try {
    world.add_contact_body(b);  // every value is checked above; this refuses only an empty or overlapping run
  } catch (const Error& e) {
    o.fail("contact", e.what());
  }
}

namespace {

// How far a particle's centre is behind a collider surface at distance `height` above it, m, and whether that is
// more than rounding (lengths up to `scale` m). A centre on the surface or above it (a contact radius overlapping)
// is a resting contact the first sub-step settles, as the built-in scenes place their bodies.
bool inside(double height, double scale, double& depth) {
  depth = -height;
  return depth > 1e-6 * (1.0 + scale);
}

}  // namespace

void check_starts_outside(const WorldDescription& d, const std::vector<std::pair<Index, Index>>& bodies,
                          const std::vector<std::string>& plane_paths, const std::vector<std::string>& sphere_paths,
                          const std::string& file) {
  if (d.planes.empty() && d.spheres.empty()) return;
  auto fail = [&](Index i, double depth, const std::string& collider) {
    std::size_t b = 0;
    while (b + 1 < bodies.size() && i >= bodies[b + 1].first) ++b;
    json_fail(file, message("/bodies/", b),
              message("particle ", i - bodies[b].first, " of this body starts ", depth, " m inside the collider at ",
                      collider, ": the first sub-step would push it out at once and keep the push as velocity; "
                      "place the body outside the collider"));
  };
  for (Index i = 0; i < d.num_particles(); ++i) {
    if (d.inverse_masses[i] == 0.0) continue;  // pinned: never moved, never pushed
    const Eigen::Vector3d x = d.positions.col(i);
    double depth = 0;
    for (std::size_t k = 0; k < d.planes.size(); ++k) {
      const PlaneDescription& pl = d.planes[k];
      if (inside(pl.normal.dot(x) - pl.offset, std::abs(pl.offset) + x.norm(), depth))
        fail(i, depth, plane_paths[k]);
    }
    for (std::size_t k = 0; k < d.spheres.size(); ++k) {
      const SphereDescription& s = d.spheres[k];
      if (inside((x - s.center).norm() - s.radius, s.radius + s.center.norm() + x.norm(), depth))
        fail(i, depth, sphere_paths[k]);
    }
  }
}

}  // namespace pbd::detail
