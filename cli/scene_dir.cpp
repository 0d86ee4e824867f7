#include "scene_dir.hpp"

#include "data_dir.hpp"
#include "pbd/error.hpp"

#include <cstdlib>
#include <system_error>

namespace pbd::cli {
namespace {

bool is_folder(const std::filesystem::path& dir) {
  std::error_code ec;
  return !dir.empty() && std::filesystem::is_directory(dir, ec);
}

// The rule of io's load_scene_by_name: such a name is a file, not a built-in scene.
bool names_a_file(const std::string& name) {
  return std::filesystem::path(name).has_extension() || name.find('/') != std::string::npos;
}

}  // namespace

std::filesystem::path builtin_scene_dir() {
  if (const char* env = std::getenv("PBD_SCENE_DIR"); env && *env) {
    if (!is_folder(env)) throw Error(std::string("PBD_SCENE_DIR: ") + env + " is not a folder");
    return env;
  }
  const std::filesystem::path data = data_dir();
  if (!data.empty() && is_folder(data / "scenes")) return data / "scenes";
  const std::string tried =
      data.empty() ? std::string("share/pbd/scenes beside the program (/proc/self/exe cannot be read)")
                   : (data / "scenes").string() + " (beside the program " + program_file().string() + ")";
  throw Error("the built-in scenes are not found: PBD_SCENE_DIR is not set and " + tried +
              " is not a folder; set PBD_SCENE_DIR to the scenes folder, or give a scene file");
}

std::vector<std::string> builtin_scene_names() { return scene_names(builtin_scene_dir()); }

Scene load_builtin_scene(const std::string& name_or_file) {
  return load_scene_by_name(name_or_file, names_a_file(name_or_file) ? std::filesystem::path() : builtin_scene_dir());
}

}  // namespace pbd::cli
