#pragma once
// The scenes pbd generates rather than reads from a file, offered by name in every command (list, run, color,
// study --scene) like the built-in scenes:
//  - "cloth<N>": the hanging cloth (N×N particles on a 1 m square, two corners pinned, PBD stretch k = 1 and XPBD
//    bending of one material for every N), 1 s (60 steps at 60 Hz) for every N, 2 ≤ N ≤ 4096;
//  - "cloth<N>-rest": the same cloth with damping, run until it hangs at rest: its exact RMS stretch is 0;
//  - "chain30": 30 links of 10 g hanging from a pin, XPBD compliance α = 1e-3 m/N, damped to rest: link k (from
//    the top) carries the weight T_k of the particles below it and stretches by exactly α·T_k.
// A built-in scene file of the same name wins (scene_dir.hpp); the study measures these scenes against their
// closed forms (study_scenes.hpp).
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pbd::cli {

/// A generated scene offered by name, for `pbd list`.
struct GeneratedScene {
  std::string name;         ///< e.g. cloth100
  long particles = 0;       ///< its particles
  std::string description;  ///< one line
};

/// The generated scenes `pbd list` shows (any cloth<N>, cloth<N>-rest with 2 ≤ N ≤ 4096 is accepted too).
std::vector<GeneratedScene> generated_scenes();

/// The scene JSON of a generated scene's name (io's scene format), or nothing when `name` is not one.
std::optional<nlohmann::json> generated_scene_json(const std::string& name);

/// N of "cloth<N>" (and whether it is "cloth<N>-rest") when `name` has that form with 2 ≤ N ≤ 4096.
std::optional<int> cloth_resolution(const std::string& name, bool* rest = nullptr);

/// chain30: what its closed form needs (the link count, α, the mass of each particle, |g|, the chain's length).
struct ChainConstants {
  static constexpr int links = 30;
  static constexpr double compliance = 1e-3, link_mass = 0.01, length = 1.0, gravity = 9.81;
};
inline constexpr const char* kChainName = "chain30";

/// How the names are described in messages: "cloth<N> or cloth<N>-rest for 2 <= N <= 4096, chain30".
inline constexpr const char* kGeneratedNamesHint = "cloth<N> or cloth<N>-rest for 2 <= N <= 4096";

}  // namespace pbd::cli
