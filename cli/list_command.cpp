// `pbd list`: the scenes pbd can run, one line each: the built-in scenes with their description and size, then the
// generated scenes (hanging cloths, the cloth at rest, the compliant chain; generated_scenes.hpp). Every name it
// prints works in run, color and study --scene.
#include "commands.hpp"
#include "scene_dir.hpp"
#include "generated_scenes.hpp"

#include <cstdio>
#include <stdexcept>

namespace pbd::cli {

void add_list_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("list", "List the scenes every command accepts (built-in and generated), one line each");
  cmd->callback([] {
    for (const std::string& name : builtin_scene_names()) {
      const Scene s = load_builtin_scene(name);
      std::printf("%-14s %7d particles %8zu constraints  %s\n", name.c_str(), int(s.world.num_particles()),
                  s.world.num_constraints(), s.description.c_str());
    }
    for (const GeneratedScene& g : generated_scenes())
      std::printf("%-14s %7ld particles %8s              generated: %s\n", g.name.c_str(), g.particles,
                  "", g.description.c_str());
    std::fflush(stdout);
    if (std::ferror(stdout)) throw std::runtime_error("cannot write to standard output");
  });
}

}  // namespace pbd::cli
