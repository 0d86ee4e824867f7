#include "study_scenes.hpp"

#include "pbd/error.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <optional>

namespace pbd::cli {
namespace {

// N of "cloth<N>" with 2 ≤ N ≤ 4096, if `name` has that form.
std::optional<int> cloth_resolution(const std::string& name) {
  const std::string prefix = "cloth";
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  int n = 0;
  const char* first = name.data() + prefix.size();
  const char* last = name.data() + name.size();
  const auto [end, ec] = std::from_chars(first, last, n);
  if (ec != std::errc() || end != last || n < 2 || n > 4096) return std::nullopt;
  return n;
}

// The hanging cloth of the scaling study: N×N particles on a 1 m square at z = 1, the two corners of one edge
// pinned, PBD stretch k = 1 on every triangle edge and dihedral bending k = 0.05, no colliders and no damping (so
// energy drift measures the solver). Steps: 60 at N = 100, fewer for bigger cloths (at least 5).
std::string hanging_cloth_json(int n) {
  const int steps = std::clamp(int(600000.0 / (double(n) * n) + 0.5), 5, 100);
  const std::string side = std::to_string(n);
  const nlohmann::json scene = {
      {"name", "cloth" + side},
      {"description", "Hanging cloth for scaling: " + side + "x" + side +
                          " particles, two corners pinned, PBD stretch (k = 1) and bending (k = 0.05)"},
      {"dt", 1.0 / 60.0},
      {"substeps", 1},
      {"iterations", 10},
      {"steps", steps},
      {"primary_error", "stretch"},
      {"bodies",
       {{{"type", "cloth"},
         {"resolution", n},
         {"size", 1.0},
         {"mass", 1.0},
         {"origin", {0.0, 0.0, 1.0}},
         {"pin", "corners"},
         {"stretch", {{"stiffness", 1.0}}},
         {"bending", {{"stiffness", 0.05}}}}}}};
  return scene.dump();
}

std::string valid_names() {
  std::string s;
  for (const auto& n : builtin_scene_names()) {
    if (!s.empty()) s += ", ";
    s += n;
  }
  for (const auto& n : generated_scene_names()) s += ", " + n;
  return s;
}

bool is_file(const std::string& name) {
  return std::filesystem::path(name).has_extension() || name.find('/') != std::string::npos;
}

}  // namespace

std::vector<std::string> generated_scene_names() { return {"cloth30", "cloth100", "cloth300", "cloth1000"}; }

bool is_generated_cloth(const std::string& name) {
  if (!cloth_resolution(name) || is_file(name)) return false;
  const auto builtin = builtin_scene_names();
  return std::find(builtin.begin(), builtin.end(), name) == builtin.end();
}

void check_study_scene(const std::string& name) {
  if (cloth_resolution(name)) return;
  const auto builtin = builtin_scene_names();
  if (std::find(builtin.begin(), builtin.end(), name) != builtin.end()) return;
  if (is_file(name)) {
    if (!std::filesystem::exists(name)) throw Error("--scene: no such scene file \"" + name + "\"");
    return;
  }
  throw Error("--scene: unknown scene \"" + name + "\" (valid: " + valid_names() +
              ", cloth<N> for 2 <= N <= 4096, or a .json file)");
}

Scene load_study_scene(const std::string& name) {
  check_study_scene(name);
  if (is_generated_cloth(name)) return parse_scene(hanging_cloth_json(*cloth_resolution(name)), name + " (generated)");
  return load_builtin_scene(name);
}

}  // namespace pbd::cli
