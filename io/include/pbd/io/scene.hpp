#pragma once
/// \file scene.hpp
/// Scenes: JSON files naming particles or generators, constraint sets, contact bodies, colliders (with their
/// materials) and step parameters. The format is documented in docs/scenes.md; any unknown key, wrong type or
/// out-of-range value is a pbd::Error naming the file and the key (as a JSON Pointer, e.g.
/// "cloth.json: /bodies/0/resolution: ..."), and so is a key given twice in one object or arrays and objects nested
/// more than 64 deep. Malformed JSON names the line and column (a number beyond double range such as 1e400 also its
/// key). Every number must fit float (the scene runs in either precision). Limits, checked from the bodies' size keys
/// before any body is built: a scene text of at most 64 MiB, 50 million particles and 200 million constraints in all
/// (the first body past a limit is refused by its size key). The name is a plain file name (it names output files).
#include "pbd/io/world_description.hpp"

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace pbd {

/// Where one body of a scene landed in its world: a run of consecutive particles and its surface triangles.
struct SceneBody {
  std::string name;                             ///< "<type>_<i>": its type and index in the scene's "bodies", e.g. "rope_0"
  Index first_particle = 0;                     ///< world index of its first particle
  Index num_particles = 0;                      ///< number of consecutive particles it has
  std::vector<std::array<Index, 3>> triangles;  ///< its surface triangles (world particle indices), if any
  static constexpr Index kNoSurface = ~Index(0);  ///< a body whose triangles do not tear
  Index surface = kNoSurface;  ///< the world's surface (World::add_surface) its triangles are, when they tear
};

/// A loaded scene: the world it describes, without a precision (build it with build_world<Real>(scene.world),
/// build_world.hpp), and metadata.
struct Scene {
  std::string name;                              ///< the scene's name
  std::string description;                       ///< one line saying what it shows
  std::string source;                            ///< file it came from (or the name given to parse_scene)
  WorldDescription world;                        ///< particles, constraints with rest values, colliders, step parameters
  int steps = 100;                               ///< the scene's suggested number of steps
  /// The error its results are judged by: "stretch", "bending", "area", "volume", "penetration" or "anchor"
  /// ("" = not stated: `pbd study` takes volume if it has any, else stretch, else its first type).
  std::string primary_error;
  std::vector<std::array<Index, 3>> triangles;   ///< surface triangles of all its bodies together (as in `bodies`)
  std::vector<SceneBody> bodies;                 ///< its bodies in file order; together they hold every particle
};

/// Parses scene JSON text; `source` names it in error messages. Nothing is returned half-built: it throws or succeeds.
Scene parse_scene(const std::string& json_text, const std::string& source);

/// Loads a scene file.
Scene load_scene(const std::filesystem::path& file);

/// Names of the scenes in folder `dir` (its files NAME.json), sorted; empty if `dir` cannot be read.
std::vector<std::string> scene_names(const std::filesystem::path& dir);

/// Loads a scene by name from folder `dir` (NAME.json) or, if `name_or_file` has an extension or a '/', from that
/// file. An unknown name is an error listing the scenes of `dir`.
Scene load_scene_by_name(const std::string& name_or_file, const std::filesystem::path& dir);

}  // namespace pbd
