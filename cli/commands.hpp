#pragma once
// Subcommands of the pbd program: each registers its options on the CLI11 app and runs when chosen.
//
// The program knows no source tree: it finds what it ships with (the built-in scenes, the study's plot script) in
// share/pbd beside its own folder (data_dir.hpp), installed or in the build tree. The product commands (list, run,
// color) use only pbd::io, that folder and the generated scenes (generated_scenes.hpp); `pbd study` (study_*.hpp)
// adds the study, whose harness (load sampling, the commit it is given, the plot call) is the library pbd_study in
// study/. main.cpp gives every error one style and status (2).
#include <CLI/CLI.hpp>

namespace pbd::cli {

/// `pbd study`: runs scenes and reports speed with the error reached.
void add_study_command(CLI::App& app);

/// `pbd color`: prints the coloring statistics of a scene's constraints.
void add_color_command(CLI::App& app);

/// `pbd list`: the built-in scenes and the generated ones (generated_scenes.hpp), one line each.
void add_list_command(CLI::App& app);

/// `pbd run`: steps a scene, writes its frames as OBJ files, reports time per step and volume errors.
void add_run_command(CLI::App& app);

}  // namespace pbd::cli
