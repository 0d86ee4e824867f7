#pragma once
// Where the pbd program finds its scenes: the built-in scene files (pbd::io takes the folder as a parameter) and the
// generated ones (generated_scenes.hpp), so that every command accepts every name `pbd list` shows.
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

/// Whether `name` names a file rather than a scene (it has an extension or a '/': io's load_scene_by_name's rule).
bool names_a_file(const std::string& name);

/// Whether `name` is a built-in scene (a file NAME.json in builtin_scene_dir()).
bool is_builtin_scene(const std::string& name);

/// Whether `name` is a generated scene (generated_scenes.hpp) and no built-in scene or file of that name.
bool is_generated_scene(const std::string& name);

/// Every scene name the commands accept, for messages: the built-in ones, then the generated ones `pbd list` shows,
/// then the hint for any cloth<N>.
std::string known_scene_names();

/// Loads a scene by file path, built-in name or generated name (in that order, as `pbd list` shows them; a file
/// needs no scene folder); throws pbd::Error listing the names when it is none of them.
Scene load_builtin_scene(const std::string& name_or_file);

}  // namespace pbd::cli
