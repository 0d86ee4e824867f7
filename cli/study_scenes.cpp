#include "study_scenes.hpp"

#include "pbd/error.hpp"
#include "scene_variants.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

// The material of every generated cloth: 1 kg on 1 m², PBD stretch k = 1, XPBD dihedral bending of compliance
// kBendingCompliance per interior edge. A dihedral angle θ over an edge of a regular mesh of spacing h stands for a
// curvature θ/h over an area ~h², so the energy θ²/(2α) of one edge is D·(θ/h)²·h²/2 = D·θ²/2 for a bending
// stiffness D: the same α at every N is the same material (D = 1/α = 1e-3 N·m), and XPBD's compliance, unlike PBD's
// stiffness, does not depend on the number of sweeps. 1000 is the value the issue measured cloth300 with.
constexpr double kBendingCompliance = 1000.0;
constexpr double kDt = 1.0 / 60.0;
constexpr int kClothSteps = 60;  // 1 s for every N
// cloth<N>-rest: damping of the slowest (pendulum) modes near critical, and 4 s, so the swing has died out.
constexpr double kRestDamping = 6.0;
constexpr int kRestSteps = 240;
// chain30: 30 links of 10 g, α = 1e-3 m/N, 1 m long, hanging straight down from its pin at rest length.
constexpr int kChainLinks = 30;
constexpr double kChainCompliance = 1e-3, kChainMass = 0.01, kChainLength = 1.0, kGravity = 9.81;
constexpr double kChainDamping = 10.0;
constexpr int kChainSteps = 120;
// A quasi-static run counts as settled when its particles moved less than 1 mm (RMS) over the steps its error is
// averaged over. Not their speed: with many substeps, a residual correction δ of each substep is a velocity δ/h,
// large for small h however still the cloth hangs.
constexpr double kSettledMotion = 1e-3;

// N of "cloth<N>" (or "cloth<N>-rest" with `rest`) with 2 ≤ N ≤ 4096, if `name` has that form.
std::optional<int> cloth_resolution(const std::string& name, bool* rest = nullptr) {
  const std::string prefix = "cloth", suffix = "-rest";
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  std::size_t end_digits = name.size();
  const bool is_rest = name.size() > prefix.size() + suffix.size() &&
                       name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  if (is_rest) end_digits -= suffix.size();
  int n = 0;
  const char* first = name.data() + prefix.size();
  const char* last = name.data() + end_digits;
  const auto [end, ec] = std::from_chars(first, last, n);
  if (ec != std::errc() || end != last || n < 2 || n > 4096) return std::nullopt;
  if (rest) *rest = is_rest;
  return n;
}

json hanging_cloth_json(int n, bool rest) {
  const std::string side = std::to_string(n);
  json scene = {
      {"name", "cloth" + side + (rest ? "-rest" : "")},
      {"description", "Hanging cloth " + side + "x" + side + ", 1 m, 1 kg, two corners pinned, PBD stretch (k = 1), "
                          "XPBD bending (compliance 1000)" +
                          (rest ? ", damped 6/s for 4 s until it hangs at rest (exact RMS stretch: 0)" : ", 1 s")},
      {"dt", kDt},
      {"substeps", 1},
      {"iterations", 10},
      {"steps", rest ? kRestSteps : kClothSteps},
      {"primary_error", "stretch"},
      {"bodies",
       {{{"type", "cloth"},
         {"resolution", n},
         {"size", 1.0},
         {"mass", 1.0},
         {"origin", {0.0, 0.0, 1.0}},
         {"pin", "corners"},
         {"stretch", {{"stiffness", 1.0}}},
         {"bending", {{"compliance", kBendingCompliance}}}}}}};
  if (rest) scene["damping"] = kRestDamping;  // no damping otherwise: energy drift measures the solver
  return scene;
}

json chain_json() {
  return {{"name", "chain30"},
          {"description", "30-link compliant chain (10 g links, alpha = 1e-3 m/N, 1 m) hanging from a pin, damped "
                          "to rest: link k stretches by exactly alpha * (weight below it)"},
          {"dt", kDt},
          {"substeps", 1},
          {"iterations", 10},
          {"steps", kChainSteps},
          {"damping", kChainDamping},
          {"gravity", {0.0, 0.0, -kGravity}},
          {"primary_error", "stretch"},
          {"bodies",
           {{{"type", "rope"},
             {"particles", kChainLinks + 1},
             {"length", kChainLength},
             {"mass", kChainMass},
             {"origin", {0.0, 0.0, 1.0}},
             {"direction", {0.0, 0.0, -1.0}},
             {"stretch", {{"compliance", kChainCompliance}}}}}}};
}

bool is_file(const std::string& name) {
  return std::filesystem::path(name).has_extension() || name.find('/') != std::string::npos;
}

bool is_builtin(const std::string& name) {
  if (is_file(name)) return false;
  const auto builtin = builtin_scene_names();
  return std::find(builtin.begin(), builtin.end(), name) != builtin.end();
}

bool is_generated(const std::string& name) {
  return !is_file(name) && !is_builtin(name) && (name == "chain30" || cloth_resolution(name));
}

std::string valid_names() {
  std::string s;
  for (const auto& n : builtin_scene_names()) s += (s.empty() ? "" : ", ") + n;
  for (const auto& g : generated_scenes()) s += ", " + g.name;
  return s;
}

// The scene's JSON and the source to parse it under (a file's own path, so that its OBJ files are found).
json scene_json(const std::string& name, std::string& source) {
  check_study_scene(name);
  if (is_generated(name)) {
    source = name + " (generated)";
    if (name == "chain30") return chain_json();
    bool rest = false;
    const int n = *cloth_resolution(name, &rest);
    return hanging_cloth_json(n, rest);
  }
  const std::filesystem::path file = is_file(name) ? std::filesystem::path(name)
                                                   : builtin_scene_dir() / (name + ".json");
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot read the scene file");
  source = file.string();
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw Error(file.string() + ": not JSON (" + e.what() + ")");
  }
}

}  // namespace

std::vector<GeneratedScene> generated_scenes() {
  std::vector<GeneratedScene> out;
  for (int n : {30, 100, 300, 1000})
    out.push_back({"cloth" + std::to_string(n), long(n) * n,
                   hanging_cloth_json(n, false).at("description").get<std::string>() +
                       " (any cloth<N>, 2 <= N <= 4096)"});
  for (int n : {30, 100})
    out.push_back({"cloth" + std::to_string(n) + "-rest", long(n) * n,
                   hanging_cloth_json(n, true).at("description").get<std::string>()});
  out.push_back({"chain30", kChainLinks + 1, chain_json().at("description").get<std::string>()});
  return out;
}

bool is_generated_cloth(const std::string& name) { return is_generated(name) && name != "chain30"; }
bool is_generated_scene(const std::string& name) { return is_generated(name); }

void check_study_scene(const std::string& name) {
  if (name == "chain30" || cloth_resolution(name)) return;
  if (is_builtin(name)) return;
  if (is_file(name)) {
    if (!std::filesystem::exists(name)) throw Error("--scene: no such scene file \"" + name + "\"");
    return;
  }
  throw Error("--scene: unknown scene \"" + name + "\" (valid: " + valid_names() +
              ", cloth<N> or cloth<N>-rest for 2 <= N <= 4096, or a .json file)");
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
  if (name == "chain30" && !is_builtin(name)) {
    a = {"chain", kChainLinks, kChainCompliance, kChainMass, kGravity, kChainLength / kChainLinks, kSettledMotion};
  } else if (cloth_resolution(name, &rest) && rest && !is_builtin(name)) {
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

std::vector<ExtraMeasure> known_answer_measures() {
  return {{"extension_pct", "link extension error", "% of alpha*T"},
          {"curve_pct", "fiber force off its curve", "% of the yield force"}};
}

}  // namespace pbd::cli
