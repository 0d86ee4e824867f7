#include "scene_dir.hpp"

#include "data_dir.hpp"
#include "generated_scenes.hpp"
#include "pbd/error.hpp"

#include <algorithm>
#include <cstdlib>
#include <system_error>

namespace pbd::cli {
namespace {

bool is_folder(const std::filesystem::path& dir) {
  std::error_code ec;
  return !dir.empty() && std::filesystem::is_directory(dir, ec);
}

}  // namespace

bool names_a_file(const std::string& name) {
  return std::filesystem::path(name).has_extension() || name.find('/') != std::string::npos;
}

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

bool is_builtin_scene(const std::string& name) {
  if (names_a_file(name)) return false;
  const std::vector<std::string> names = builtin_scene_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

// A generated name: a built-in file of that name wins, but a generated scene needs no scene folder.
bool builtin_scene_named(const std::string& generated_name) {
  try {
    return is_builtin_scene(generated_name);
  } catch (const Error&) {
    return false;
  }
}

bool is_generated_scene(const std::string& name) {
  return !names_a_file(name) && generated_scene_json(name) && !builtin_scene_named(name);
}

std::string known_scene_names() {
  std::string s;
  for (const std::string& n : builtin_scene_names()) s += n + ", ";
  for (const GeneratedScene& g : generated_scenes()) s += g.name + ", ";
  return s + "or " + kGeneratedNamesHint;
}

Scene load_builtin_scene(const std::string& name_or_file) {
  if (names_a_file(name_or_file)) return load_scene(name_or_file);
  const auto generated = generated_scene_json(name_or_file);
  if (generated ? builtin_scene_named(name_or_file) : is_builtin_scene(name_or_file))
    return load_scene(builtin_scene_dir() / (name_or_file + ".json"));
  if (generated) return parse_scene(generated->dump(), name_or_file + " (generated)");
  throw Error("unknown scene \"" + name_or_file + "\" (the scenes: " + known_scene_names() + "; or a .json file)");
}

}  // namespace pbd::cli
