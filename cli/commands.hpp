#pragma once
// Subcommands of the pbd program: each registers its options on the CLI11 app and runs when chosen.
#include <CLI/CLI.hpp>

namespace pbd::cli {

/// `pbd study`: runs scenes and reports speed with the error reached.
void add_study_command(CLI::App& app);

/// `pbd color`: prints the coloring statistics of a scene's constraints.
void add_color_command(CLI::App& app);

/// `pbd list`: the built-in scenes and the study's generated cloths, one line each.
void add_list_command(CLI::App& app);

/// `pbd run`: steps a scene, writes its frames as OBJ files, reports time per step and volume errors.
void add_run_command(CLI::App& app);

}  // namespace pbd::cli
