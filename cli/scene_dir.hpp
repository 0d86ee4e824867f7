#pragma once
// Where the pbd program finds its built-in scenes; pbd::io takes the folder as a parameter.
#include "pbd/io/scene.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace pbd::cli {

/// Folder of the built-in scenes: $PBD_SCENE_DIR if set; else the source tree's scenes/ this program was configured
/// from, if it exists; else ../share/pbd/scenes next to the program (an installed copy, wherever it was moved); else
/// the installation's share/pbd/scenes; else "scenes".
std::filesystem::path builtin_scene_dir();

/// Names of the built-in scenes (files NAME.json in builtin_scene_dir()), sorted.
std::vector<std::string> builtin_scene_names();

/// Loads a scene by built-in name or by file path.
Scene load_builtin_scene(const std::string& name_or_file);

}  // namespace pbd::cli
