#pragma once
// The study's plots: `pbd study --plots DIR` hands its JSON report to plot_study.py (matplotlib), which writes the
// PNG and SVG plots and summary.md. The script is installed beside the program (share/pbd/plot_study.py; the build
// tree links it to scripts/plot_study.py) unless --plot-script names it; the interpreter is python3 on PATH unless
// --python names it (scripts/study names Debian's, which has python3-matplotlib).
#include <filesystem>
#include <string>

namespace pbd::cli {

/// The script and the interpreter that run it.
struct PlotTools {
  std::string script;                    ///< --plot-script / $PBD_PLOT_SCRIPT; "" = default_script
  std::string python = "python3";        ///< --python, else $PBD_PYTHON, else python3: a path, or a name on PATH
  std::filesystem::path default_script;  ///< share/pbd/plot_study.py beside the program (set by the caller)
};

/// Checks, before a study, that its plots can be drawn: the script is a file and the interpreter starts and imports
/// matplotlib (`python -c "import matplotlib"`); throws pbd::Error naming what is missing.
void check_plot_tools(const PlotTools& tools);

/// Runs `python script json dir` and waits for it; throws pbd::Error naming the script path tried when it does not
/// exist, and the command when it cannot start or fails.
void run_plot_script(const PlotTools& tools, const std::filesystem::path& json, const std::filesystem::path& dir);

}  // namespace pbd::cli
