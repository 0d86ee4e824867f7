#pragma once
// Where the pbd program finds its built-in scenes; pbd::io takes the folder as a parameter.
#include "pbd/io/scene.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace pbd::cli {

/// Folder of the built-in scenes: $PBD_SCENE_DIR if set, else data_dir()/scenes (share/pbd/scenes beside the
/// program's folder: the installed copy, or the build tree's link to the source tree's scenes/). Throws pbd::Error
/// naming the folders tried when neither is a folder.
std::filesystem::path builtin_scene_dir();

/// Names of the built-in scenes (files NAME.json in builtin_scene_dir()), sorted.
std::vector<std::string> builtin_scene_names();

/// Loads a scene by built-in name or by file path (a name with an extension or a '/', as io's load_scene_by_name
/// reads it; a file needs no scene folder).
Scene load_builtin_scene(const std::string& name_or_file);

}  // namespace pbd::cli
