// `pbd list`: the scenes pbd can run, one line each: the built-in scenes with their description and size, then the
// generated hanging cloths of the study.
#include "commands.hpp"
#include "scene_dir.hpp"
#include "study_scenes.hpp"

#include <cstdio>
#include <stdexcept>

namespace pbd::cli {

void add_list_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("list", "List the built-in scenes and the study's generated cloths, one line each");
  cmd->callback([] {
    for (const std::string& name : builtin_scene_names()) {
      const Scene s = load_builtin_scene(name);
      std::printf("%-14s %7d particles %8zu constraints  %s\n", name.c_str(), int(s.world.num_particles()),
                  s.world.num_constraints(), s.description.c_str());
    }
    for (const std::string& name : generated_scene_names()) {
      const int n = std::stoi(name.substr(5));
      std::printf("%-14s %7d particles %8s              generated hanging cloth %dx%d for the study: two corners "
                  "pinned, PBD stretch and bending (any cloth<N>, 2 <= N <= 4096)\n", name.c_str(), n * n, "", n, n);
    }
    std::fflush(stdout);
    if (std::ferror(stdout)) throw std::runtime_error("cannot write to standard output");
  });
}

}  // namespace pbd::cli
