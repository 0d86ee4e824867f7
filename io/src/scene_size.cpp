#include "scene_size.hpp"

#include "json_reader.hpp"
#include "pbd/constraint_types.hpp"
#include "pbd/detail/message.hpp"

#include <algorithm>
#include <cmath>

namespace pbd::detail {
namespace {

// What one body asks for, at most; counted in double (exact to 2^53, and no overflow for 3 × 50M³).
struct Size {
  double particles = 0;
  double constraints = 0;
  std::string key;  // the key that sets its size, named in the error
};

// The integer under `key` if it is one the strict reader takes (in [0, hi]); `fallback` when absent; 0 otherwise,
// leaving the error to the strict reader, which names the key and the range.
double count(const nlohmann::json& o, const char* key, double hi, double fallback = 0) {
  const auto it = o.find(key);
  if (it == o.end()) return fallback;
  if (!it->is_number_integer()) return 0;
  const double v = it->get<double>();
  return v >= 0 && v <= hi ? v : 0;
}

// A count for a message: the integer itself below 10^18 (exact in double up to 2^53, and every size here is a
// product of exact integers), else a bound.
std::string shown(double n) {
  return n < 1e18 ? std::to_string(std::uint64_t(n)) : std::string("more than 10^18");
}

// Elements of the array under `key` (0 when absent or not an array).
double elements(const nlohmann::json& o, const char* key) {
  const auto it = o.find(key);
  return it != o.end() && it->is_array() ? double(it->size()) : 0.0;
}

bool has(const nlohmann::json& o, const char* key) { return o.contains(key); }

// Constraints a body's listed-type keys ask for (SceneForm::listed, e.g. "anchors"): one per entry of "particles".
double listed_constraints(const nlohmann::json& b) {
  double n = 0;
  for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    if constexpr (C::kSceneForm == SceneForm::listed) {
      const auto it = b.find(C::kSceneKey);
      if (it != b.end() && it->is_object()) n += elements(*it, "particles");
    }
  });
  return n;
}

// A triangle mesh of v vertices, e edges and t triangles with the constraint sets `o` asks for.
Size surface(const nlohmann::json& o, double v, double e, double t, std::string key) {
  const double constraints = (has(o, StretchConstraint<double>::kSceneKey) ? e : 0) +
                             (has(o, BendingConstraint<double>::kSceneKey) ? e : 0) +
                             (has(o, AreaConstraint<double>::kSceneKey) ? t : 0) +
                             (has(o, "volume") ? 1 : 0);
  return {v, constraints, std::move(key)};
}

// Tethers a body's "tethers" key asks for, at most: one per particle, or with "to": "all" one per particle and
// source (its pins: a cloth's edge or corners, a rope's first particle, a mesh's "pinned"; and its anchors).
double tether_constraints(const nlohmann::json& b, double particles) {
  const auto it = b.find("tethers");
  if (it == b.end() || (it->is_boolean() && !it->get<bool>())) return 0;
  const auto to = it->is_object() ? it->find("to") : it->end();
  if (!it->is_object() || to == it->end() || *to != "all") return particles;
  double sources = elements(b, "pinned") + 1;  // a rope's pin
  const auto anchors = b.find(AnchorConstraint<double>::kSceneKey);
  if (anchors != b.end() && anchors->is_object()) sources += elements(*anchors, "particles");
  const auto pin = b.find("pin");
  const auto type = b.find("type");
  if (type != b.end() && *type == "cloth" && (pin == b.end() || *pin != "none"))
    sources += pin != b.end() && *pin == "edge" ? count(b, "resolution", 4096) : 2;
  return particles * sources;
}

Size body_size(const nlohmann::json& b) {
  const auto type = b.find("type");
  if (type == b.end() || !type->is_string()) return {};
  const std::string t = type->get<std::string>();
  if (t == "cloth") {
    const double n = count(b, "resolution", 4096);
    return surface(b, n * n, 3 * n * n, 2 * n * n, "resolution");
  }
  if (t == "rope") {
    const double m = count(b, "particles", double(kMaxSceneParticles));
    return {m, has(b, StretchConstraint<double>::kSceneKey) ? m : 0, "particles"};
  }
  if (t == "grains") {
    const auto c = b.find("count");
    if (c == b.end() || !c->is_array() || c->size() != 3) return {};
    double n = 1;
    for (const auto& v : *c) {
      const double k = v.is_number_integer() ? v.get<double>() : 0.0;
      n *= k >= 1 && k <= double(kMaxSceneParticles) ? k : 0.0;
    }
    return {n, 0, "count"};
  }
  if (t == "tets") {  // a box: (nx + 1)(ny + 1)(nz + 1) vertices, 6 tets per cell, one constraint per key per tet
    const auto g = b.find("generator");
    if (g == b.end() || !g->is_object()) return {};
    const auto c = g->find("cells");
    if (c == g->end() || !c->is_array() || c->size() != 3) return {};
    double v = 1, cells = 1;
    for (const auto& x : *c) {
      const double k = x.is_number_integer() ? x.get<double>() : 0.0;
      const double ok = k >= 1 && k <= double(kMaxSceneParticles) ? k : 0.0;
      v *= ok + 1;
      cells *= ok;
    }
    const double per_tet = double(has(b, TetVolumeConstraint<double>::kSceneKey)) +
                           double(has(b, NeoHookeanConstraint<double>::kSceneKey)) +
                           double(has(b, TetFiberConstraint<double>::kSceneKey));
    const double clusters = has(b, ShapeMatchConstraint<double>::kSceneKey) ? v : 0;  // one per vertex
    const double edges = has(b, StretchConstraint<double>::kSceneKey) ? 7 * cells : 0;  // a Kuhn cube adds 7 edges
    return {v, 6 * cells * per_tet + clusters + edges, "generator/cells"};
  }
  if (t == "particles") {
    const auto s = b.find(StretchConstraint<double>::kSceneKey);
    return {elements(b, "positions"), s != b.end() && s->is_object() ? elements(*s, "pairs") : 0, "positions"};
  }
  if (t == "mesh") {
    const auto g = b.find("generator");
    if (g == b.end() || !g->is_object() || !g->contains("type") || !(*g)["type"].is_string()) return {};
    const std::string gt = (*g)["type"].get<std::string>();
    if (gt == "grid") {
      const double n = count(*g, "resolution", 4096);
      return surface(b, n * n, 3 * n * n, 2 * n * n, "generator/resolution");
    }
    if (gt == "icosphere") {
      const double f = std::pow(4.0, count(*g, "level", 8, 2));
      return surface(b, 10 * f + 2, 30 * f, 20 * f, "generator/level");
    }
    if (gt == "tube") {
      const double s = count(*g, "segments", 1e5, 16), r = count(*g, "rings", 1e5, 8);
      const auto capped = g->find("capped");
      const double caps = capped != g->end() && capped->is_boolean() && capped->get<bool>() ? 2 : 0;
      const double tris = 2 * s * r + caps * s;  // the rings' quads and the caps' fans
      return surface(b, s * r + caps, 3 * tris, tris, "generator/rings");
    }
    if (gt == "dodecahedron") return surface(b, 32, 90, 60, "generator");
  }
  return {};  // an OBJ mesh is sized when it is loaded; an unknown type is the strict reader's error
}

}  // namespace

void check_scene_size(const nlohmann::json& root, const std::string& file) {
  const auto bodies = root.find("bodies");
  if (bodies == root.end() || !bodies->is_array()) return;
  double particles = 0, constraints = 0;
  for (std::size_t i = 0; i < bodies->size(); ++i) {
    const nlohmann::json& b = (*bodies)[i];
    if (!b.is_object()) continue;
    Size s = body_size(b);
    s.constraints += listed_constraints(b) + tether_constraints(b, s.particles);
    const std::string path = message("/bodies/", i, "/", s.key.empty() ? "type" : s.key);
    if (particles + s.particles > double(kMaxSceneParticles))
      json_fail(file, path, message("this body has ", shown(s.particles), " particles; with the ", shown(particles),
                                    " of the bodies before it the scene would exceed its limit of ",
                                    kMaxSceneParticles, " particles"));
    if (constraints + s.constraints > double(kMaxSceneConstraints))
      json_fail(file, path, message("this body has up to ", shown(s.constraints), " constraints; with the ",
                                    shown(constraints),
                                    " of the bodies before it the scene would exceed its limit of ",
                                    kMaxSceneConstraints, " constraints"));
    particles += s.particles;
    constraints += s.constraints;
  }
}

}  // namespace pbd::detail
