#include "generated_scenes.hpp"

#include <charconv>

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
// chain30: hanging straight down from its pin at rest length, damped so that it settles within its 2 s.
constexpr double kChainDamping = 10.0;
constexpr int kChainSteps = 120;

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
  using C = ChainConstants;
  return {{"name", kChainName},
          {"description", "30-link compliant chain (10 g links, alpha = 1e-3 m/N, 1 m) hanging from a pin, damped "
                          "to rest: link k stretches by exactly alpha * (weight below it)"},
          {"dt", kDt},
          {"substeps", 1},
          {"iterations", 10},
          {"steps", kChainSteps},
          {"damping", kChainDamping},
          {"gravity", {0.0, 0.0, -C::gravity}},
          {"primary_error", "stretch"},
          {"bodies",
           {{{"type", "rope"},
             {"particles", C::links + 1},
             {"length", C::length},
             {"mass", C::link_mass},
             {"origin", {0.0, 0.0, 1.0}},
             {"direction", {0.0, 0.0, -1.0}},
             {"stretch", {{"compliance", C::compliance}}}}}}};
}

}  // namespace

std::optional<int> cloth_resolution(const std::string& name, bool* rest) {
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

std::optional<json> generated_scene_json(const std::string& name) {
  if (name == kChainName) return chain_json();
  bool rest = false;
  if (const auto n = cloth_resolution(name, &rest)) return hanging_cloth_json(*n, rest);
  return std::nullopt;
}

std::vector<GeneratedScene> generated_scenes() {
  std::vector<GeneratedScene> out;
  for (int n : {30, 100, 300, 1000})
    out.push_back({"cloth" + std::to_string(n), long(n) * n,
                   hanging_cloth_json(n, false).at("description").get<std::string>() +
                       " (any cloth<N>, 2 <= N <= 4096)"});
  for (int n : {30, 100})
    out.push_back({"cloth" + std::to_string(n) + "-rest", long(n) * n,
                   hanging_cloth_json(n, true).at("description").get<std::string>()});
  out.push_back({kChainName, ChainConstants::links + 1, chain_json().at("description").get<std::string>()});
  return out;
}

}  // namespace pbd::cli
