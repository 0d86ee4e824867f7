#include "study_scenes.hpp"

#include "json_file.hpp"
#include "pbd/error.hpp"
#include "scene_variants.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

// A quasi-static run counts as settled when its particles moved less than 1 mm (RMS) over the steps its error is
// averaged over. Not their speed: with many substeps, a residual correction δ of each substep is a velocity δ/h,
// large for small h however still the cloth hangs.
constexpr double kSettledMotion = 1e-3;

// The largest scene file read, as pbd::load_scene's: a scene file names generators and meshes, it holds none.
constexpr std::uintmax_t kMaxSceneFileBytes = 64u << 20;

bool is_generated(const std::string& name) { return is_generated_scene(name); }

// The scene's JSON and the source to parse it under (a file's own path, so that its OBJ files are found).
json scene_json(const std::string& name, std::string& source) {
  check_study_scene(name);
  if (is_generated(name)) {
    source = name + " (generated)";
    return *generated_scene_json(name);
  }
  const std::filesystem::path file = names_a_file(name) ? std::filesystem::path(name)
                                                   : builtin_scene_dir() / (name + ".json");
  source = file.string();
  // Read as the report is (json_file.hpp): a FIFO is refused before it can block, nesting is bounded.
  return read_json_file(file, "scene file", kMaxSceneFileBytes);
}

}  // namespace

bool is_generated_cloth(const std::string& name) { return is_generated(name) && name != kChainName; }

void check_study_scene(const std::string& name) {
  if (generated_scene_json(name)) return;
  if (names_a_file(name)) {
    std::error_code ec;
    const auto status = std::filesystem::status(name, ec);
    if (!std::filesystem::exists(status)) throw Error("--scene: no such scene file \"" + name + "\"");
    // Before it is opened: a FIFO would block the study's first read.
    if (!std::filesystem::is_regular_file(status))
      throw Error("--scene: \"" + name + "\" is not a regular file");
    return;
  }
  if (is_builtin_scene(name)) return;
  throw Error("--scene: unknown scene \"" + name + "\" (the scenes: " + known_scene_names() + "; or a .json file)");
}

Scene load_study_scene(const std::string& name, const std::string& variant) {
  std::string source;
  const json doc = apply_variant(scene_json(name, source), variant);
  Scene scene = parse_scene(doc.dump(), source);
  if (is_generated(name)) scene.name = name;
  return scene;
}

std::vector<std::string> study_variants(const std::string& name, const std::vector<std::string>& requested,
                                        bool keep_unparsed) {
  std::string source;
  const json doc = scene_json(name, source);
  if (requested.empty() && !is_generated(name)) return {"plain"};
  std::vector<std::string> out;
  for (const std::string& v : requested.empty() ? variant_names() : requested) {
    if (!variant_applies(doc, v)) continue;
    if (requested.empty() && v != "plain" && !keep_unparsed) {
      try {
        (void)parse_scene(apply_variant(doc, v).dump(), source);
      } catch (const Error& e) {
        std::fprintf(stderr, "pbd study: %s: variant %s left out: this build does not parse it (%s)\n", name.c_str(),
                     v.c_str(), e.what());
        continue;
      }
    }
    out.push_back(v);
  }
  return out;
}

KnownAnswer known_answer(const std::string& name) {
  KnownAnswer a;
  bool rest = false;
  using C = ChainConstants;
  if (name == kChainName && is_generated(name)) {
    a = {"chain", C::links, C::compliance, C::link_mass, C::gravity, C::length / C::links, kSettledMotion};
  } else if (cloth_resolution(name, &rest) && rest && is_generated(name)) {
    a.kind = "rest";
    a.settled_motion = kSettledMotion;
  }
  return a;
}

KnownAnswer known_answer(const SceneInfo& info) {
  if (info.known_answer == "curve") return KnownAnswer{"curve"};
  return known_answer(info.base);
}

namespace {

double force_scale(const Material& m) {
  if (m.yield_strain < Material::kNever) return m.force(m.yield_strain);
  if (m.rupture_strain < Material::kNever) return m.force(m.rupture_strain);
  return m.stiffness;
}

// Calls f(type) for each built-in type that may follow a curve (fibers, tet fibers).
template <class Real, class F> void for_each_material_type(F&& f) {
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
    if constexpr (takes_material<typename decltype(type)::type>()) f(type);
  });
}

}  // namespace

template <class Real> bool has_curve(const World<Real>& world) {
  bool any = false;
  for_each_material_type<Real>([&](auto type) {
    for (const auto& c : world.template constraints<typename decltype(type)::type>())
      any = any || world.constraint_sets()[c.set].curve() != nullptr;
  });
  return any;
}

template <class Real> Errors curve_errors(const World<Real>& world) {
  double sum2 = 0.0, max = 0.0;
  std::size_t n = 0;
  auto add = [&](const Material* m, double elastic, double force) {  // one force (a tet fiber's: stress)
    if (!m || std::isnan(force)) return;
    const double e = 100.0 * std::abs(force - m->force(elastic)) / force_scale(*m);
    sum2 += e * e;
    max = std::max(max, std::isfinite(e) ? e : INFINITY);
    ++n;
  };
  for_each_material_type<Real>([&](auto type) {  // each one's against its curve
    using C = typename decltype(type)::type;
    const auto& items = world.template constraints<C>();
    const std::vector<FiberReading> readings = world.template material_readings<C>();
    for (std::size_t k = 0; k < items.size(); ++k) {
      const FiberReading& r = readings[k];
      add(world.constraint_sets()[items[k].set].curve(), r.strain - r.plastic, r.force);
    }
  });
  // Those the last step broke, at their break: one that a solve left far off its curve (a step that overshot to
  // the rupture strain with little force) counts as such, rather than leaving the run with nothing to judge.
  for (const FiberBreak& b : world.last_breaks())
    add(world.constraint_sets()[b.set].curve(), b.strain - b.plastic, b.force);
  Errors out;
  out["curve_pct"] = {n ? std::sqrt(sum2 / double(n)) : 0.0, max};
  return out;
}

template bool has_curve(const World<float>&);
template bool has_curve(const World<double>&);
template Errors curve_errors(const World<float>&);
template Errors curve_errors(const World<double>&);

Errors known_answer_errors(const KnownAnswer& a, const Matrix3X<double>& x) {
  Errors out;
  if (a.kind != "chain" || x.cols() < a.links + 1) return out;
  double sum2 = 0.0, max = 0.0;
  for (int k = 1; k <= a.links; ++k) {
    // Link k joins particles k−1 and k; it carries the particles k .. links.
    const double tension = double(a.links - k + 1) * a.link_mass * a.gravity;
    const double exact = a.compliance * tension;
    const double extension = (x.col(k) - x.col(k - 1)).norm() - a.rest_length;
    const double e = 100.0 * std::abs(extension - exact) / exact;
    sum2 += e * e;
    max = std::max(max, std::isfinite(e) ? e : INFINITY);
  }
  out["extension_pct"] = {std::sqrt(sum2 / a.links), max};
  return out;
}

}  // namespace pbd::cli
