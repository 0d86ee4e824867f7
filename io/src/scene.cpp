#include "pbd/io/scene.hpp"

#include "json_reader.hpp"
#include "scene_contact.hpp"
#include "scene_size.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/checks.hpp"
#include "pbd/closed_mesh.hpp"
#include "pbd/io/description_builder.hpp"
#include "pbd/io/frame_series.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/obj_loader.hpp"
#include "pbd/io/tet_body.hpp"
#include "pbd/io/tet_mesh_reader.hpp"
#include "pbd/io/tetrahedralize.hpp"
#include "pbd/step_limits.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <vector>

namespace pbd {
namespace {

using detail::JsonObject;
using detail::kInf;
using detail::message;

constexpr std::uintmax_t kMaxSceneBytes = 64u << 20;  // a scene file names generators, not meshes: 64 MiB is plenty
constexpr long kMaxParticles = detail::kMaxSceneParticles;
// The keys of the types a body's mesh makes (SceneForm::mesh), as their headers declare them; the generators below
// know which edges and triangles each one takes.
constexpr const char* kStretchKey = StretchConstraint<double>::kSceneKey;
constexpr const char* kBendingKey = BendingConstraint<double>::kSceneKey;
constexpr const char* kAreaKey = AreaConstraint<double>::kSceneKey;

// Throws unless a body of `count` particles still fits in the scene's particle limit: checked before anything is
// generated, so a huge resolution is refused instead of allocated.
void check_particle_budget(const JsonObject& o, const std::string& key, const DescriptionBuilder& world,
                           std::uint64_t count) {
  const std::uint64_t have = world.num_particles();
  if (count > std::uint64_t(kMaxParticles) - std::min(have, std::uint64_t(kMaxParticles)))
    o.fail(key, message("this body has ", count, " particles; with the ", have, " before it the scene would exceed its "
                        "limit of ", kMaxParticles, " particles"));
}

// A scene's name names its files (frames, reports): a plain file name, so that nothing lands outside the folder given.
void check_scene_name(const JsonObject& o, const std::string& name) {
  if (name.size() > 100) o.fail("name", message("a scene name is at most 100 bytes; this one has ", name.size()));
  try {
    check_frame_stem(name);  // the rule of frame_series.hpp: no '/', '\\', control characters, "." or ".."
  } catch (const Error& e) {
    o.fail("name", message("a scene name must be a plain file name: ", e.what()));
  }
}

// A direction or normal: non-zero and of finite length.
Eigen::Vector3d direction(const JsonObject& o, const std::string& key, const std::array<double, 3>& a) {
  const Eigen::Vector3d v(a[0], a[1], a[2]);
  const double length = v.norm();
  if (!(length > 0.0) || !std::isfinite(length))
    o.fail(key, length > 0.0 ? "is too long (its length overflows)" : "must not be the zero vector (or too short)");
  return v;
}

Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// The largest magnitude a scene's speeds may have (a velocity, gravity × dt): its square, which energies and
// contacts take, still fits in float.
const double kMaxSafe = std::sqrt(double(std::numeric_limits<float>::max()));

// A velocity (m/s) read at `path`: its square must fit in float (kMaxSafe).
Eigen::Vector3d velocity(const nlohmann::json& v, const std::string& file, const std::string& path) {
  const Eigen::Vector3d u = vec(detail::json_vec3(v, file, path));
  if (!(u.norm() <= kMaxSafe))
    detail::json_fail(file, path, message("a speed of ", u.norm(), " m/s is beyond ", kMaxSafe,
                                          " m/s (its square must fit in float)"));
  return u;
}

// A stress–strain curve (pbd/material.hpp): {"stiffness": k (N per unit strain), "toe_strain", "yield_strain",
// "hardening" (N per unit plastic strain), "rupture_strain"}; the strains left out are never reached (toe: 0).
Material read_material(const JsonObject& o) {
  Material m;
  m.stiffness = o.number("stiffness", 0.0, kInf);
  m.toe_strain = o.number("toe_strain", 0.0, kInf, 0.0);
  m.yield_strain = o.number("yield_strain", 0.0, kInf, Material::kNever);
  m.hardening = o.number("hardening", 0.0, kInf, 0.0);
  m.rupture_strain = o.number("rupture_strain", 0.0, kInf, Material::kNever);
  o.reject_unknown_keys();
  if (const std::string why = m.error(); !why.empty()) o.fail(why.substr(0, why.find(' ')), why);
  return m;
}

// XPBD compliance `key` of `o`: α / h² (h the sub-step), which every sweep takes, must fit in float, or the
// sweeps turn it into infinity and the positions into NaN.
double compliance(const JsonObject& o, const std::string& key, const StepParams<double>& p) {
  const double alpha = o.number(key, 0.0, kInf);
  const double h = p.dt / p.substeps;
  if (alpha / (h * h) > double(std::numeric_limits<float>::max()))
    o.fail(key, message("compliance ", alpha, " over the sub-step squared (h = dt / substeps = ", h, " s) is ",
                        alpha / (h * h), ", beyond the range of float"));
  return alpha;
}

// {"stiffness": k, "iteration_independent": bool}, {"compliance": α} or {"material": {...}}; empty object =
// stiffness 1. `p`: the scene's step (read first), against which a compliance is checked.
Stiffness read_stiffness(const JsonObject& o, const StepParams<double>& p) {
  if (o.has("material")) {
    if (o.has("stiffness") || o.has("compliance") || o.has("iteration_independent"))
      o.fail("material", "a set with a material takes no stiffness or compliance of its own");
    return Stiffness::fiber(read_material(o.object("material")));
  }
  const bool has_k = o.has("stiffness"), has_a = o.has("compliance");
  if (has_k && has_a) o.fail("compliance", "give either stiffness (PBD) or compliance (XPBD), not both");
  if (has_a) {
    if (o.has("iteration_independent")) o.fail("iteration_independent", "only applies to stiffness, not compliance");
    return Stiffness::xpbd_compliance(compliance(o, "compliance", p));
  }
  const double k = has_k ? o.number("stiffness", 0.0, 1.0) : 1.0;
  return o.boolean("iteration_independent", false) ? Stiffness::iteration_independent(k) : Stiffness::pbd_k(k);
}

// Local particle index of a body at `path`, checked against its particle count.
Index local_index(const nlohmann::json& v, const std::string& file, const std::string& path, Index count) {
  return Index(detail::json_integer(v, file, path, 0, long(count) - 1));
}

std::optional<Index> read_stretch_set(const JsonObject& body, DescriptionBuilder& world) {
  if (!body.has(kStretchKey)) return std::nullopt;
  const JsonObject s = body.object(kStretchKey);
  const Index set = world.add_constraint_set(read_stiffness(s, world.description().params));
  s.reject_unknown_keys();
  return set;
}

// Optional constraint-set object `key` (a stiffness object): a new set, or nothing.
std::optional<Index> read_set(const JsonObject& body, const std::string& key, DescriptionBuilder& world) {
  if (!body.has(key)) return std::nullopt;
  const JsonObject s = body.object(key);
  const Index set = world.add_constraint_set(read_stiffness(s, world.description().params));
  s.reject_unknown_keys();
  return set;
}

// "bending", "area" and (if allowed) "volume": {stiffness..., "pressure": {"from", "to", "duration"}}.
MeshConstraintSets read_surface_sets(const JsonObject& body, DescriptionBuilder& world, bool allow_volume) {
  MeshConstraintSets sets;
  sets.bending = read_set(body, kBendingKey, world);
  sets.area = read_set(body, kAreaKey, world);
  if (allow_volume && body.has("volume")) {
    const JsonObject v = body.object("volume");
    sets.volume = world.add_constraint_set(read_stiffness(v, world.description().params));
    if (v.has("pressure")) {
      const JsonObject p = v.object("pressure");
      sets.pressure.from = p.number("from", 1e-6, 1e6, 1.0);
      sets.pressure.to = p.number("to", 1e-6, 1e6, sets.pressure.from);
      sets.pressure.duration = p.number("duration", 0.0, 1e9, 0.0);
      p.reject_unknown_keys();
    }
    v.reject_unknown_keys();
  }
  return sets;
}

// "generator": {"type": "grid" | "dodecahedron" | "icosphere" | "tube", parameters...}; its vertex count is checked
// against the particles the scene has left before the mesh is made.
TriangleMesh read_generator(const JsonObject& g, const DescriptionBuilder& world) {
  const std::string type = g.string("type");
  TriangleMesh m;
  if (type == "grid") {
    const long n = g.integer("resolution", 2, 4096);
    check_particle_budget(g, "resolution", world, std::uint64_t(n) * std::uint64_t(n));
    m = grid_mesh(int(n), g.number("size", 1e-6, 1e6, 1.0));
  } else if (type == "dodecahedron") {
    check_particle_budget(g, "type", world, 32);
    m = dodecahedron_mesh(g.number("radius", 1e-6, 1e6, 1.0));
  } else if (type == "icosphere") {
    const int level = int(g.integer("level", 0, 8, 2));
    check_particle_budget(g, "level", world, 10 * (std::uint64_t(1) << (2 * level)) + 2);
    m = icosphere_mesh(level, g.number("radius", 1e-6, 1e6, 1.0));
  } else if (type == "tube") {
    const int segments = int(g.integer("segments", 3, 100000, 16));
    const int rings = int(g.integer("rings", 2, 100000, 8));
    const double radius = g.number("radius", 1e-6, 1e6, 0.1);
    const double length = g.number("length", 1e-6, 1e6, 1.0);
    const bool capped = g.boolean("capped", false);
    check_particle_budget(g, "rings", world, std::uint64_t(segments) * std::uint64_t(rings) + (capped ? 2 : 0));
    m = tube_mesh(segments, rings, radius, length, capped);
  } else {
    g.fail("type", message("unknown generator ", detail::quoted(type),
                           " (expected \"grid\", \"dodecahedron\", \"icosphere\" or \"tube\")"));
  }
  g.reject_unknown_keys();
  return m;
}

// A triangle mesh from a generator or an OBJ file (relative to the scene file), placed, with the constraint sets
// it asks for.
Body read_mesh(const JsonObject& o, DescriptionBuilder& world) {
  if (o.has("generator") == o.has("obj")) o.fail("generator", "give exactly one of \"generator\" and \"obj\"");
  TriangleMesh mesh;
  std::string obj_file;
  if (o.has("obj")) {
    const std::string name = o.string("obj");
    if (name.empty()) o.fail("obj", "the file name is empty");  // JsonObject::string refused a NUL character
    const std::filesystem::path file = std::filesystem::path(o.file()).parent_path() / name;
    obj_file = file.string();
    try {
      mesh = load_obj(file);
    } catch (const Error& e) {
      o.fail("obj", e.what());
    }
    check_particle_budget(o, "obj", world, mesh.num_vertices());
    if (o.has("volume"))  // named as the OBJ file numbers them, from 1
      if (const auto defect = closed_mesh_defect(mesh.triangles, mesh.num_vertices(), 1))
        o.fail("obj", message(file.string(), ": a volume needs a closed mesh: ", *defect,
                              " (vertex numbers as in the file, from 1)"));
  } else {
    mesh = read_generator(o.object("generator"), world);
  }
  MeshBodyOptions opts;
  opts.scale = o.number("scale", 1e-9, 1e9, 1.0);
  opts.origin = o.vec3("origin", opts.origin);
  opts.mass = o.number("mass", 1e-12, 1e12, 1.0);
  if (o.has("pinned"))
    for (const auto& [v, path] : o.array("pinned")) opts.pinned.push_back(local_index(*v, o.file(), path, mesh.num_vertices()));
  MeshConstraintSets sets;
  sets.stretch = read_set(o, kStretchKey, world);
  const MeshConstraintSets surface = read_surface_sets(o, world, true);
  sets.bending = surface.bending;
  sets.area = surface.area;
  sets.volume = surface.volume;
  sets.pressure = surface.pressure;
  try {
    return add_mesh(world, mesh, opts, sets);
  } catch (const Error& e) {  // e.g. a volume on a flat or inside-out mesh: named with the OBJ file it came from
    o.fail(o.has("obj") ? "obj" : "generator", o.has("obj") ? message(obj_file, ": ", e.what()) : e.what());
  }
}

// A tet body's "generator": {"type": "box", "cells": [nx, ny, nz], "size": [x, y, z]} (its vertex count checked
// against the particles the scene has left before the mesh is made) or {"type": "ball", "level", "radius",
// "max_volume"} (an icosphere of that level, at most 10242 vertices, filled with tets by tetgen).
TetMesh read_tet_generator(const JsonObject& g, const DescriptionBuilder& world) {
  const std::string type = g.string("type");
  if (type == "ball") {  // an icosphere's surface (read_generator's) filled by tetgen
    const int level = int(g.integer("level", 0, 5, 2));
    const double radius = g.number("radius", 1e-6, 1e6, 1.0);
    TetrahedralizeOptions t;
    t.max_volume = g.number("max_volume", 0.0, 1e9, t.max_volume);
    g.reject_unknown_keys();
    try {
      return tetrahedralize(icosphere_mesh(level, radius), t, "ball");
    } catch (const Error& e) {
      g.fail("type", e.what());
    }
  }
  if (type != "box")
    g.fail("type", message("unknown tet generator ", detail::quoted(type), " (expected \"box\" or \"ball\")"));
  const auto cells = g.array("cells");
  if (cells.size() != 3) g.fail("cells", message("expected [nx, ny, nz] (3 integers), got ", cells.size(), " values"));
  std::array<int, 3> n{};
  std::uint64_t vertices = 1;
  for (int a = 0; a < 3; ++a) {
    n[a] = int(detail::json_integer(*cells[a].first, g.file(), cells[a].second, 1, kMaxParticles));
    vertices = std::min<std::uint64_t>(vertices * std::uint64_t(n[a] + 1), std::uint64_t(kMaxParticles) + 1);
  }
  check_particle_budget(g, "cells", world, vertices);
  const std::array<double, 3> size = g.vec3("size", {1.0, 1.0, 1.0});
  for (int a = 0; a < 3; ++a)
    if (!(size[a] > 0.0) || !std::isfinite(size[a])) g.fail("size", message("component ", a, " must be > 0"));
  g.reject_unknown_keys();
  return tet_box_mesh(n, size);
}

// "clamped": "x_min" | "x_max" | "y_min" | "y_max" | "z_min" | "z_max": pins the vertices on that face of the
// mesh's bounding box (tet_mesh_face_vertices).
std::vector<Index> read_clamped(const JsonObject& o, const TetMesh& mesh) {
  const std::string face = o.string("clamped");
  static constexpr const char* kFacesNames[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
  for (int f = 0; f < 6; ++f)
    if (face == kFacesNames[f]) return tet_mesh_face_vertices(mesh, f / 2, f % 2 == 1);
  o.fail("clamped", message("expected \"x_min\", \"x_max\", \"y_min\", \"y_max\", \"z_min\" or \"z_max\", got ",
                            detail::quoted(face)));
}

// A file name relative to the scene file, from key `key`; empty refused (JsonObject::string refused a NUL character).
std::filesystem::path scene_relative_file(const JsonObject& o, const std::string& key) {
  const std::string name = o.string(key);
  if (name.empty()) o.fail(key, "the file name is empty");
  return std::filesystem::path(o.file()).parent_path() / name;
}

// A tet body's mesh: exactly one of "generator" (a box), "file" (Gmsh .msh or TetGen .node/.ele) and "obj" (a
// closed surface filled with tets by tetgen, with "max_volume" (m³, 0: no limit) and "max_radius_edge_ratio").
TetMesh read_tet_mesh(const JsonObject& o, const DescriptionBuilder& world) {
  const int given = int(o.has("generator")) + int(o.has("file")) + int(o.has("obj"));
  if (given != 1) o.fail("generator", "give exactly one of \"generator\", \"file\" and \"obj\"");
  if (o.has("generator")) return read_tet_generator(o.object("generator"), world);
  const std::string key = o.has("file") ? "file" : "obj";
  const std::filesystem::path file = scene_relative_file(o, key);
  TetMesh mesh;
  try {
    if (key == "file") {
      mesh = load_tet_mesh(file);
    } else {
      TetrahedralizeOptions t;
      t.max_volume = o.number("max_volume", 0.0, 1e9, t.max_volume);
      t.max_radius_edge_ratio = o.number("max_radius_edge_ratio", 1.0, 100.0, t.max_radius_edge_ratio);
      mesh = tetrahedralize(load_obj(file), t, file.string());
    }
  } catch (const Error& e) {
    o.fail(key, e.what());
  }
  check_particle_budget(o, key, world, mesh.num_vertices());
  return mesh;
}

// A volumetric body: {"type": "tets", mesh (read_tet_mesh), "vertex_order", "origin", "scale", "density", "pinned": [...],
// "clamped": face, "tet_volume": stiffness, "neo_hookean": {"young": E, "poisson": nu},
// "shape_matching": {stiffness..., "beta": β}, "stretch": stiffness or {"material": curve} on every edge,
// "tet_fibers": {"direction": a0, stiffness or {"material": curve, stiffness E in Pa}} on every tet}.
Body read_tets(const JsonObject& o, DescriptionBuilder& world) {
  TetMesh mesh = read_tet_mesh(o, world);
  const std::string order = o.has("vertex_order") ? o.string("vertex_order") : "mesh";
  if (order == "spatial") mesh = spatially_ordered(mesh);
  else if (order != "mesh")
    o.fail("vertex_order", message("unknown vertex order ", detail::quoted(order), " (expected \"mesh\" or \"spatial\")"));
  TetBodyOptions opts;
  opts.scale = o.number("scale", 1e-9, 1e9, 1.0);
  opts.origin = o.vec3("origin", opts.origin);
  opts.density = o.number("density", 1e-9, 1e9, opts.density);
  if (o.has("pinned"))
    for (const auto& [v, path] : o.array("pinned")) opts.pinned.push_back(local_index(*v, o.file(), path, mesh.num_vertices()));
  if (o.has("clamped")) {
    const std::vector<Index> clamped = read_clamped(o, mesh);
    opts.pinned.insert(opts.pinned.end(), clamped.begin(), clamped.end());
  }
  TetConstraintSets sets;
  sets.volume = read_set(o, TetVolumeConstraint<double>::kSceneKey, world);
  if (o.has(NeoHookeanConstraint<double>::kSceneKey)) {
    const JsonObject m = o.object(NeoHookeanConstraint<double>::kSceneKey);
    const double young = m.number("young", 1e-9, 1e15);
    const double poisson = m.number("poisson", -1.0, 0.5);
    if (!(poisson > -1.0 && poisson < 0.5)) m.fail("poisson", message("must be in (-1, 0.5), got ", poisson));
    const NeoHookeanMaterial material = young_poisson(young, poisson);
    sets.neo_hookean = world.add_constraint_set(Stiffness::xpbd_compliance(material.compliance()));
    sets.ratio = material.ratio();
    m.reject_unknown_keys();
  }
  if (o.has(ShapeMatchConstraint<double>::kSceneKey)) {  // a stiffness object and "beta"
    const JsonObject m = o.object(ShapeMatchConstraint<double>::kSceneKey);
    sets.beta = m.number("beta", 0.0, 1.0, 0.0);
    sets.shape_match = world.add_constraint_set(read_stiffness(m, world.description().params));
    m.reject_unknown_keys();
  }
  sets.stretch = read_stretch_set(o, world);  // on every edge: fibers when it has a curve (they tear the tets)
  if (o.has(TetFiberConstraint<double>::kSceneKey)) {  // {"direction": a0, stiffness or {"material": curve in Pa}}
    const JsonObject f = o.object(TetFiberConstraint<double>::kSceneKey);
    const Eigen::Vector3d a = direction(f, "direction", f.vec3("direction"));
    sets.direction = {a.x(), a.y(), a.z()};
    sets.fibers = world.add_constraint_set(read_stiffness(f, world.description().params));
    f.reject_unknown_keys();
  }
  if (!sets.volume && !sets.neo_hookean && !sets.shape_match && !sets.fibers)
    o.fail("generator", "a tet body needs \"neo_hookean\", \"tet_volume\", \"shape_matching\" or \"tet_fibers\": "
                        "without one nothing holds it");
  try {
    return add_tet_body(world, mesh, opts, sets);
  } catch (const Error& e) {
    o.fail(o.has("generator") ? "generator" : o.has("file") ? "file" : "obj", e.what());
  }
}

Body read_cloth(const JsonObject& o, DescriptionBuilder& world) {
  ClothOptions c;
  c.resolution = int(o.integer("resolution", 2, 4096));
  check_particle_budget(o, "resolution", world, std::uint64_t(c.resolution) * std::uint64_t(c.resolution));
  c.size = o.number("size", 1e-6, 1e6, c.size);
  c.mass = o.number("mass", 1e-12, 1e12, c.mass);
  c.origin = o.vec3("origin", c.origin);
  const std::string pin = o.string("pin", "corners");
  if (pin == "corners") c.pin = ClothPin::corners;
  else if (pin == "edge") c.pin = ClothPin::edge;
  else if (pin == "none") c.pin = ClothPin::none;
  else o.fail("pin", message("expected \"corners\", \"edge\" or \"none\", got ", detail::quoted(pin)));
  const std::optional<Index> stretch = read_stretch_set(o, world);
  const MeshConstraintSets sets = read_surface_sets(o, world, false);
  Body body = add_cloth(world, c, stretch);
  add_mesh_constraints(world, body.triangles, sets);
  return body;
}

Body read_rope(const JsonObject& o, DescriptionBuilder& world) {
  RopeOptions r;
  r.particles = int(o.integer("particles", 2, kMaxParticles));
  check_particle_budget(o, "particles", world, std::uint64_t(r.particles));
  r.length = o.number("length", 1e-6, 1e6, r.length);
  r.mass = o.number("mass", 1e-12, 1e12, r.mass);
  r.end_mass = o.number("end_mass", 1e-12, 1e15, r.mass);
  r.origin = o.vec3("origin", r.origin);
  r.direction = o.vec3("direction", r.direction);
  direction(o, "direction", r.direction);
  return add_rope(world, r, read_stretch_set(o, world));
}

// "grains": "count" [nx, ny, nz] (required), "spacing" (required), "origin", "jitter", "seed", "mass", "velocity";
// the count is checked against the particles the scene has left before anything is made.
Body read_grains(const JsonObject& o, DescriptionBuilder& world) {
  GrainsOptions g;
  const auto count = o.array("count");
  if (count.size() != 3) o.fail("count", message("expected [nx, ny, nz] (3 integers), got ", count.size(), " values"));
  for (int axis = 0; axis < 3; ++axis)
    g.count[axis] = int(detail::json_integer(*count[axis].first, o.file(), count[axis].second, 1, kMaxParticles));
  const std::uint64_t nxy = std::uint64_t(g.count[0]) * std::uint64_t(g.count[1]);  // ≤ kMaxParticles²: no overflow
  if (nxy > std::uint64_t(kMaxParticles))
    o.fail("count", message("nx × ny alone is ", nxy, " particles, more than the scene's limit of ", kMaxParticles));
  check_particle_budget(o, "count", world, nxy * std::uint64_t(g.count[2]));
  g.spacing = o.number("spacing", 1e-9, 1e6);
  g.origin = o.vec3("origin", g.origin);
  g.jitter = o.number("jitter", 0.0, 0.5, g.jitter);
  if (g.jitter >= 0.5) o.fail("jitter", "must be below 0.5 (a fraction of the spacing, in [0, 0.5))");
  g.seed = std::uint64_t(o.integer("seed", 0, std::numeric_limits<long>::max(), long(g.seed)));
  g.mass = o.number("mass", 1e-12, 1e15, g.mass);
  if (o.has("velocity")) {
    const Eigen::Vector3d v = velocity(o.value("velocity"), o.file(), o.path("velocity"));
    g.velocity = {v.x(), v.y(), v.z()};
  }
  return add_grains(world, g);
}

// Explicit particles: "positions" (required), "masses" or "mass", optional "velocities", "pinned",
// "stretch": {"pairs": [[a, b], ...], stiffness...}.
Body read_particles(const JsonObject& o, DescriptionBuilder& world) {
  const auto positions = o.array("positions");
  if (positions.empty()) o.fail("positions", "needs at least one particle");
  check_particle_budget(o, "positions", world, positions.size());
  const Index n = Index(positions.size());
  Matrix3X<double> x(3, n);
  for (Index i = 0; i < n; ++i) x.col(i) = vec(detail::json_vec3(*positions[i].first, o.file(), positions[i].second));
  Eigen::VectorXd m(n);
  if (o.has("masses")) {
    if (o.has("mass")) o.fail("mass", "give either mass (each particle) or masses (one per particle), not both");
    const auto masses = o.array("masses");
    if (masses.size() != n) o.fail("masses", message("has ", masses.size(), " entries for ", n, " positions"));
    for (Index i = 0; i < n; ++i) m[i] = detail::json_number(*masses[i].first, o.file(), masses[i].second, 1e-12, 1e15);
  } else {
    m.setConstant(o.number("mass", 1e-12, 1e15, 1.0));
  }
  if (o.has("pinned"))
    for (const auto& [v, path] : o.array("pinned")) m[local_index(*v, o.file(), path, n)] = DescriptionBuilder::kPinned;
  Matrix3X<double> vel = Matrix3X<double>::Zero(3, n);
  if (o.has("velocities")) {
    const auto vs = o.array("velocities");
    if (vs.size() != n) o.fail("velocities", message("has ", vs.size(), " entries for ", n, " positions"));
    for (Index i = 0; i < n; ++i) vel.col(i) = velocity(*vs[i].first, o.file(), vs[i].second);
  }
  Body b;
  b.first_particle = world.add_particles(x, m);
  b.num_particles = n;
  world.velocities().rightCols(n) = vel;
  if (o.has(kStretchKey)) {
    const JsonObject s = o.object(kStretchKey);
    const Index set = world.add_constraint_set(read_stiffness(s, world.description().params));
    for (const auto& [pair, path] : s.array("pairs")) {
      if (!pair->is_array() || pair->size() != 2) detail::json_fail(o.file(), path, "expected a pair [a, b]");
      const Index a = local_index((*pair)[0], o.file(), path + "/0", n);
      const Index c = local_index((*pair)[1], o.file(), path + "/1", n);
      if (a == c) detail::json_fail(o.file(), path, message("names particle ", a, " twice"));
      add_edge(world, b.first_particle + a, b.first_particle + c, set);
    }
    s.reject_unknown_keys();
  }
  return b;
}

// The largest length of a collider in a scene: the engine's for float (checks.hpp), as a scene runs in either.
const double kMaxColliderLength = double(max_collider_length<float>());

// {"type": "plane", "normal", "offset"} or {"type": "sphere", "center", "radius"}, each with the optional surface
// keys "friction" and "restitution" (scene_contact.hpp).
void read_collider(const nlohmann::json& v, const std::string& file, const std::string& path, DescriptionBuilder& world) {
  const JsonObject c(v, file, path);
  const std::string type = c.string("type");
  if (type == "plane") {
    const Eigen::Vector3d n = direction(c, "normal", c.vec3("normal"));
    const double offset = c.number("offset", -kInf, kInf, 0.0) * n.norm();  // n·x >= d with n not yet normalized
    if (!(std::abs(offset) <= double(std::numeric_limits<float>::max())))
      c.fail("offset", "offset × |normal| is beyond the range of float (the plane is stored with a unit normal)");
    if (!(std::abs(offset) <= kMaxColliderLength * n.norm()))  // a scene runs in float too
      c.fail("offset", message("must be at most ", kMaxColliderLength, " m from the origin (a contact's arithmetic "
                               "squares it, in float too), got ", offset / n.norm()));
    world.add_plane(n, offset, detail::read_contact_material(c));
  } else if (type == "sphere") {
    const Eigen::Vector3d center = vec(c.vec3("center"));
    if (!(center.cwiseAbs().maxCoeff() <= kMaxColliderLength))
      c.fail("center", message("each coordinate must be at most ", kMaxColliderLength,
                               " m from the origin (a contact's arithmetic squares it, in float too)"));
    const double radius = c.number("radius", 1e-9, kMaxColliderLength);
    world.add_sphere(center, radius, detail::read_contact_material(c));
  } else {
    c.fail("type", message("unknown collider type ", detail::quoted(type), " (expected \"plane\" or \"sphere\")"));
  }
  c.reject_unknown_keys();
}

// Runs `read` (reading the item at `path`); a pbd::Error from the engine underneath (World, generators) that does not
// name the file yet gets the file and `path` in front, so every error says where it comes from.
template <class Read> void at_path(const std::string& file, const std::string& path, Read&& read) {
  try {
    read();
  } catch (const Error& e) {
    if (std::string_view(e.what()).starts_with(detail::printable(file) + ": ")) throw;
    detail::json_fail(file, path, e.what());
  }
}

// The key of a listed constraint type C (SceneForm::listed, e.g. "anchors"): {"particles": [entries], <its scene
// fields>, stiffness...}, one constraint per entry on the body's particles (an entry is a local index, or an array of
// kArity of them); the rest values not given are measured where the particles start. The constraint is added with
// the engine's checks (DescriptionBuilder::add), an error naming the entry's path.
template <class C> void read_listed(const JsonObject& body, DescriptionBuilder& world, const Body& b) {
  if (!body.has(C::kSceneKey)) return;
  const JsonObject o = body.object(C::kSceneKey);
  C proto = blank_constraint<C>();
  proto.set = world.add_constraint_set(read_stiffness(o, world.description().params));
  FieldMask given = 0;
  for_each_field<C>([&](const auto& field, auto i) {
    if (!field.in_scene || !o.has(field.name)) return;
    if constexpr (std::is_arithmetic_v<typename std::decay_t<decltype(field)>::type>)
      proto.*field.member = o.number(field.name, -kInf, kInf);
    else
      proto.*field.member = vec(o.vec3(field.name));
    given |= FieldMask(1) << decltype(i)::value;
  });
  for (const auto& [v, path] : o.array("particles")) {
    C c = proto;
    if constexpr (C::kArity == 1) {
      c.particles[0] = b.first_particle + local_index(*v, o.file(), path, b.num_particles);
    } else {
      if (!v->is_array() || v->size() != std::size_t(C::kArity))
        detail::json_fail(o.file(), path, message("expected an array of ", C::kArity, " particle indices"));
      for (int k = 0; k < C::kArity; ++k)
        c.particles[k] = b.first_particle + local_index((*v)[k], o.file(), message(path, "/", k), b.num_particles);
    }
    at_path(o.file(), path, [&, &c = c] { world.add(c, given); });
  }
  o.reject_unknown_keys();
}

// A body's "grips": [{"particles": [local indices], "mass": kg, "velocity": [x, y, z]}, ...]: those particles get
// that velocity, and that mass (each) or, without one, are pinned: a pinned particle moves at its velocity whatever
// acts on it, so a grip pulls at exactly that speed. Read right after the body is made, before its listed
// constraints, tethers and contact body.
void read_grips(const JsonObject& body, DescriptionBuilder& world, const Body& b) {
  if (!body.has("grips")) return;
  for (const auto& [v, path] : body.array("grips")) {
    const JsonObject g(*v, body.file(), path);
    const double mass = g.has("mass") ? g.number("mass", 0.0, kInf) : DescriptionBuilder::kPinned;
    if (!(mass > 0.0)) g.fail("mass", "must be > 0");
    const Eigen::Vector3d v0 = g.has("velocity") ? velocity(g.value("velocity"), g.file(), g.path("velocity"))
                                                 : Eigen::Vector3d::Zero();
    for (const auto& [p, at] : g.array("particles")) {
      const Index i = b.first_particle + local_index(*p, g.file(), at, b.num_particles);
      world.set_mass(i, mass);
      world.velocities().col(i) = v0;
    }
    g.reject_unknown_keys();
  }
}

// A body's "tethers" (pbd/tethers.hpp): true, false, or {"to": "nearest"|"all", "length": "euclidean"|"geodesic",
// "compliance": α}; made after the body's anchors (a source), for cloth, rope and mesh bodies. A body without a
// pinned or anchored particle gets none (tethers.hpp says why).
void read_tethers(const JsonObject& body, const std::string& type, DescriptionBuilder& world, const Body& b) {
  if (!body.has("tethers")) return;
  const nlohmann::json& v = body.value("tethers");
  TetherOptions t;
  if (v.is_boolean()) {
    if (!v.get<bool>()) return;
  } else if (v.is_object()) {
    const JsonObject o = body.object("tethers");
    const std::string to = o.string("to", "nearest");
    if (const auto parsed = parse_tether_to(to)) t.to = *parsed;
    else o.fail("to", message("expected \"nearest\" or \"all\", got ", detail::quoted(to)));
    const std::string length = o.string("length", "euclidean");
    if (const auto parsed = parse_tether_length(length)) t.length = *parsed;
    else o.fail("length", message("expected \"euclidean\" or \"geodesic\", got ", detail::quoted(length)));
    t.compliance = o.has("compliance") ? compliance(o, "compliance", world.description().params) : 0.0;
    o.reject_unknown_keys();
  } else {
    body.fail("tethers", "expected true, false or an object {\"to\", \"length\", \"compliance\"}");
  }
  if (type != "cloth" && type != "rope" && type != "mesh")
    body.fail("tethers", message("tethers are made for cloth, rope and mesh bodies, not ", detail::quoted(type)));
  std::vector<Index> particles(b.num_particles);
  for (Index i = 0; i < b.num_particles; ++i) particles[i] = b.first_particle + i;
  at_path(body.file(), body.path("tethers"), [&] { world.add_tethers(particles, t); });
}

// Every listed constraint type's key of a body, in the list's order.
void read_listed_types(const JsonObject& body, DescriptionBuilder& world, const Body& b) {
  for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    if constexpr (C::kSceneForm == SceneForm::listed) read_listed<C>(body, world, b);
  });
}

// The measures a scene's primary_error may name: each built-in type's name, volume, penetration (collisions),
// overlap (particle contacts) and reference (the distance from the study's converged reference).
std::vector<std::string> error_measures() {
  std::vector<std::string> names;
  for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) { names.push_back(decltype(type)::type::kName); });
  for (const char* other : {"volume", "penetration", "overlap", "reference"}) names.push_back(other);
  return names;
}

// What a scene's primary_error `measure` (one of error_measures()) needs and `d` lacks, as the message says it
// ("the scene has no stretch constraint to measure"), or "" when `d` has it. pbd study judges the scene by it, and
// pbd run and the Python load_scene read the same scene: each refuses it here, at load.
std::string missing_measure(const WorldDescription& d, const std::string& measure) {
  bool has = measure == "reference";
  std::string what = measure + " constraint";
  if (measure == "volume") {
    has = !d.volumes.empty();
  } else if (measure == "penetration") {
    has = !d.planes.empty() || !d.spheres.empty();
    what = "collider";
  } else if (measure == "overlap") {
    for (const auto& b : d.contact_bodies) has = has || b.radius > 0.0;
    what = "contact body with a radius";
  } else {
    for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) {
      using C = typename decltype(type)::type;
      if (measure == C::kName) has = !d.constraints<C>().empty();
    });
  }
  return has ? std::string() : "the scene has no " + what + " to measure";
}

// Throws unless every particle's inverse mass is 0 (pinned) or a normal float: a scene runs in float, where the
// inverse of a mass beyond about 8.5e37 kg is subnormal or 0 (the particle would be pinned without a word) and that
// of a mass below about 2.9e-39 kg infinite.
void check_masses(const JsonObject& o, const Scene& scene) {
  const VectorX<double>& w = scene.world.inverse_masses;
  for (Index i = 0; i < Index(w.size()); ++i) {
    if (w[i] == 0.0 || (w[i] >= double(std::numeric_limits<float>::min()) &&
                        w[i] <= double(std::numeric_limits<float>::max())))
      continue;
    std::size_t b = 0;
    while (b + 1 < scene.bodies.size() && i >= scene.bodies[b].first_particle + scene.bodies[b].num_particles) ++b;
    const Index local = i - scene.bodies[b].first_particle;
    detail::json_fail(o.file(), message("/bodies/", b),
                      message("particle ", local, " of ", scene.bodies[b].name, ": a mass of ", 1.0 / w[i],
                              " kg, whose inverse (", w[i], " 1/kg) is not a normal float: in float the particle "
                              "would be pinned, or its motion lost"));
  }
}

// The top-level "hierarchy": true or false, an integer (0: off, L > 0: on with L levels), or an object {"levels": L,
// "parents": k, "sweeps": s, "slack": ε, "compliant": false, "enabled": true} (every key optional; StepParams::
// hierarchy's defaults).
Hierarchy read_hierarchy(const JsonObject& o) {
  const nlohmann::json& v = o.value("hierarchy");
  Hierarchy h;
  if (v.is_boolean()) {
    h.enabled = v.get<bool>();
  } else if (v.is_number_integer()) {
    h.levels = int(o.integer("hierarchy", 0, 16));
    h.enabled = h.levels > 0;
    if (!h.enabled) h.levels = Hierarchy{}.levels;
  } else if (v.is_object()) {
    const JsonObject j = o.object("hierarchy");
    h.enabled = j.boolean("enabled", true);
    h.levels = int(j.integer("levels", 1, 16, h.levels));
    h.parents = int(j.integer("parents", 1, 8, h.parents));
    h.sweeps = int(j.integer("sweeps", 1, 64, h.sweeps));
    h.slack = j.number("slack", 0.0, 0.1, h.slack);
    h.compliant = j.boolean("compliant", h.compliant);
    j.reject_unknown_keys();
  } else {
    o.fail("hierarchy", "expected true, false, a number of levels (0: off) or an object {\"levels\": L, \"parents\": k, "
                        "\"sweeps\": s}");
  }
  return h;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& source) {
  if (text.size() > kMaxSceneBytes)
    throw Error(message(source, ": ", text.size(), " bytes, more than the ", kMaxSceneBytes, " a scene may have"));
  const nlohmann::json root = detail::parse_json(text, source);
  const std::string& f = source;
  const JsonObject o(root, f, "");
  detail::check_scene_size(root, f);  // every body sized before any is built
  // The description is built as the scene is read, with World<double>'s checks and rest values (DescriptionBuilder);
  // an error from those gets the file and key path in front (at_path).
  DescriptionBuilder world;
  Scene scene;
  scene.source = source;
  scene.name = o.string("name");
  check_scene_name(o, scene.name);
  scene.description = o.string("description", "");
  scene.steps = int(o.integer("steps", 1, 100'000'000, 100));
  if (o.has("primary_error")) {
    scene.primary_error = o.string("primary_error");
    const std::vector<std::string> measures = error_measures();
    if (std::find(measures.begin(), measures.end(), scene.primary_error) == measures.end()) {
      std::string expected;
      for (std::size_t i = 0; i < measures.size(); ++i)
        expected += (i == 0 ? "" : i + 1 == measures.size() ? " or " : ", ") + measures[i];
      o.fail("primary_error", message("unknown error measure ", detail::quoted(scene.primary_error), " (expected ",
                                      expected, ")"));
    }
  }
  StepParams<double> p;
  p.dt = o.number("dt", 1e-9, 10.0);
  p.substeps = int(o.integer("substeps", 1, kMaxSubsteps, 1));
  p.iterations = int(o.integer("iterations", 0, kMaxIterations, 10));
  if (sweeps_per_step(p.substeps, p.iterations) > kMaxSweepsPerStep)
    o.fail(o.has("iterations") ? "iterations" : "substeps",
           message("substeps × iterations is ", sweeps_per_step(p.substeps, p.iterations), " sweeps a step, more than "
                   "the limit of ", kMaxSweepsPerStep, " (far more than any step needs to converge)"));
  p.gravity = vec(o.vec3("gravity", {0.0, 0.0, -9.81}));
  if (!(p.gravity.norm() * std::max(p.dt, 1.0) <= kMaxSafe))
    o.fail("gravity", message("|gravity| × max(dt, 1 s) is ", p.gravity.norm() * std::max(p.dt, 1.0), " m/s, beyond ",
                              kMaxSafe, " m/s (the speed it gives, squared, must fit in float)"));
  p.damping = o.number("damping", 0.0, 1e6, 0.0);
  p.collision_margin = o.number("collision_margin", 0.0, 1e6, p.collision_margin);
  if (o.has("sweep_order")) {
    const std::string order = o.string("sweep_order");
    if (const auto so = parse_sweep_order(order)) p.sweep_order = *so;
    else o.fail("sweep_order", message("unknown sweep order ", detail::quoted(order),
                                       " (expected \"forward\" or \"symmetric\")"));
  }
  if (o.has("hierarchy")) p.hierarchy = read_hierarchy(o);
  at_path(f, "", [&] { world.set_params(p); });
  if (o.has("blocking")) {  // {"constraints_per_block": n, "metis": bool}: the block solver's partition
    const JsonObject b = o.object("blocking");
    BlockOptions blocking;
    blocking.constraints_per_block = std::size_t(b.integer("constraints_per_block", 1, 1'000'000'000, 1024));
    blocking.use_metis = b.boolean("metis", true);
    b.reject_unknown_keys();
    world.set_blocking(blocking);
  }
  for (const auto& [v, path] : o.array("bodies")) {
    at_path(f, path, [&, &v = v, &path = path] {
      const JsonObject b(*v, f, path);
      const std::string type = b.string("type");
      const std::size_t surfaces = world.description().surfaces.size();
      Body body;
      if (type == "cloth") body = read_cloth(b, world);
      else if (type == "rope") body = read_rope(b, world);
      else if (type == "particles") body = read_particles(b, world);
      else if (type == "mesh") body = read_mesh(b, world);
      else if (type == "grains") body = read_grains(b, world);
      else if (type == "tets") body = read_tets(b, world);
      else b.fail("type", message("unknown body type ", detail::quoted(type),
                                  " (expected \"cloth\", \"rope\", \"particles\", \"mesh\", \"grains\" or \"tets\")"));
      read_grips(b, world, body);
      read_listed_types(b, world, body);
      read_tethers(b, type, world, body);
      detail::read_contact_body(b, body, world);
      b.reject_unknown_keys();
      scene.triangles.insert(scene.triangles.end(), body.triangles.begin(), body.triangles.end());
      scene.bodies.push_back({message(type, "_", scene.bodies.size()), body.first_particle, body.num_particles,
                              std::move(body.triangles),
                              world.description().surfaces.size() > surfaces ? Index(surfaces) : SceneBody::kNoSurface});
    });
  }
  std::vector<std::string> plane_paths, sphere_paths;
  if (o.has("colliders"))
    for (const auto& [v, path] : o.array("colliders")) {
      const std::size_t planes = world.description().planes.size();
      at_path(f, path, [&, &v = v, &path = path] { read_collider(*v, f, path, world); });
      (world.description().planes.size() > planes ? plane_paths : sphere_paths).push_back(path);
    }
  o.reject_unknown_keys();
  std::vector<std::pair<Index, Index>> runs;
  for (const SceneBody& b : scene.bodies) runs.push_back({b.first_particle, b.num_particles});
  detail::check_starts_outside(world.description(), runs, plane_paths, sphere_paths, f);
  scene.world = std::move(world).description();
  check_masses(o, scene);
  if (!scene.primary_error.empty())
    if (const std::string missing = missing_measure(scene.world, scene.primary_error); !missing.empty())
      o.fail("primary_error", missing);
  return scene;
}

Scene load_scene(const std::filesystem::path& file) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) throw Error(message(file.string(), ": cannot read the scene file (", ec.message(), ")"));
  if (size > kMaxSceneBytes)
    throw Error(message(file.string(), ": file is ", size, " bytes, more than the ", kMaxSceneBytes, " a scene may have"));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(message(file.string(), ": cannot open the scene file"));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), file.string());
}

std::vector<std::string> scene_names(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

Scene load_scene_by_name(const std::string& name, const std::filesystem::path& dir) {
  const std::filesystem::path as_file(name);
  if (as_file.has_extension() || name.find('/') != std::string::npos) return load_scene(as_file);
  const auto path = dir / (name + ".json");
  if (!std::filesystem::exists(path)) {
    std::string known;
    for (const auto& n : scene_names(dir)) known += (known.empty() ? "" : ", ") + n;
    throw Error(message("unknown scene \"", name, "\" (built-in scenes: ", known, "; or give a .json file)"));
  }
  return load_scene(path);
}

}  // namespace pbd
