#pragma once
/// \file scene.hpp
/// Scenes: JSON files naming particles or generators, constraint sets, colliders and step parameters.
/// The format is documented in docs/scenes.md; any unknown key, wrong type or out-of-range value is a pbd::Error
/// naming the file and the key (as a JSON Pointer, e.g. "cloth.json: /bodies/0/resolution: ..."), and so is a key
/// given twice in one object or arrays and objects nested more than 64 deep. Malformed JSON (also a number beyond
/// double range such as 1e400) names the line and column. Limits, checked before anything is allocated: a scene text
/// of at most 64 MiB and 50 million particles in all (a body that would pass it is refused by its size key).
#include "pbd/world.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace pbd {

/// A loaded scene: the world it builds (double precision; convert with World<float>(scene.world)) and metadata.
struct Scene {
  std::string name;                              ///< the scene's name
  std::string description;                       ///< one line saying what it shows
  std::string source;                            ///< file it came from (or the name given to parse_scene)
  World<double> world;                           ///< particles, constraints, colliders and step parameters
  int steps = 100;                               ///< the scene's suggested number of steps
  std::vector<std::array<Index, 3>> triangles;   ///< surface triangles of its bodies, for output and pictures
};

/// Parses scene JSON text; `source` names it in error messages. Nothing is returned half-built: it throws or succeeds.
Scene parse_scene(const std::string& json_text, const std::string& source);

/// Loads a scene file.
Scene load_scene(const std::filesystem::path& file);

/// Folder of the built-in scenes: $PBD_SCENE_DIR if set, else the source tree's scenes/ (or the installed copy).
std::filesystem::path builtin_scene_dir();

/// Names of the built-in scenes (files NAME.json in builtin_scene_dir()), sorted.
std::vector<std::string> builtin_scene_names();

/// Loads a scene by built-in name or by file path.
Scene load_scene_by_name(const std::string& name_or_file);

}  // namespace pbd
