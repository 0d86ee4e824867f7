#pragma once
// Where the pbd program finds the files it ships with (the built-in scenes, the study's plot script): share/pbd
// beside the folder that holds the program, found from the running program itself (/proc/self/exe), so that an
// installed or moved copy works from any folder with no source tree. No path is compiled in. The build tree has the
// same layout: cli/CMakeLists.txt links <build>/share/pbd/{scenes,plot_study.py} to the source tree's files.
#include <filesystem>

namespace pbd::cli {

/// The running program's file (/proc/self/exe, symbolic links resolved); "" when it cannot be read.
std::filesystem::path program_file();

/// <folder of the program>/../share/pbd; "" when the program's file cannot be read.
std::filesystem::path data_dir();

}  // namespace pbd::cli
