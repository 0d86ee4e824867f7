#include "scene_dir.hpp"

#include <cstdlib>
#include <system_error>

#ifndef PBD_SOURCE_SCENE_DIR
#define PBD_SOURCE_SCENE_DIR ""
#endif
#ifndef PBD_INSTALL_SCENE_DIR
#define PBD_INSTALL_SCENE_DIR ""
#endif

namespace pbd::cli {
namespace {

bool is_folder(const std::filesystem::path& dir) {
  std::error_code ec;
  return !dir.empty() && std::filesystem::is_directory(dir, ec);
}

// ../share/pbd/scenes relative to the running program's folder ("" if /proc/self/exe cannot be read).
std::filesystem::path next_to_program() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty()) return {};
  return exe.parent_path().parent_path() / "share" / "pbd" / "scenes";
}

}  // namespace

std::filesystem::path builtin_scene_dir() {
  if (const char* env = std::getenv("PBD_SCENE_DIR"); env && *env) return env;
  for (const std::filesystem::path& dir :
       {std::filesystem::path(PBD_SOURCE_SCENE_DIR), next_to_program(), std::filesystem::path(PBD_INSTALL_SCENE_DIR)})
    if (is_folder(dir)) return dir;
  return "scenes";
}

std::vector<std::string> builtin_scene_names() { return scene_names(builtin_scene_dir()); }

Scene load_builtin_scene(const std::string& name_or_file) { return load_scene_by_name(name_or_file, builtin_scene_dir()); }

}  // namespace pbd::cli
