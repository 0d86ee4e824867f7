#pragma once
// The scenes `pbd study` accepts: built-in scenes, scene files, and the generated hanging cloths "cloth<N>"
// (N×N particles, stretch + bending; cloth30 to cloth1000 are the scaling sizes).
#include "scene_dir.hpp"

#include <string>
#include <vector>

namespace pbd::cli {

/// The generated scaling scenes offered by name (any cloth<N> with 2 ≤ N ≤ 4096 is accepted).
std::vector<std::string> generated_scene_names();

/// Whether `name` is a generated hanging cloth cloth<N> (and not a built-in scene or a file).
bool is_generated_cloth(const std::string& name);

/// Loads a built-in scene, a generated cloth<N> or a scene file; throws pbd::Error listing the valid names.
Scene load_study_scene(const std::string& name_or_file);

/// Throws pbd::Error (listing the valid names) unless `name_or_file` names a scene load_study_scene can load.
void check_study_scene(const std::string& name_or_file);

}  // namespace pbd::cli
