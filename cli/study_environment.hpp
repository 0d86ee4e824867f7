#pragma once
// Where and when `pbd study` ran (machine, date, command line, git commit), and the plot script it calls.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace pbd::cli {

/// {"command" (this process's argv from /proc/self/cmdline), "date" (UTC, ISO 8601), "machine": {"nproc", "cpu",
/// "load_average_at_start"}, "git_commit" (of the source tree)}; what cannot be found is null.
nlohmann::json study_environment();

/// The context block of a report, like Google Benchmark's: {"compiler", "flags", "build_type", "cpu", "cores",
/// "date", "commit", "loadavg_start"}; what cannot be found is null.
nlohmann::json study_context();

/// The 1-, 5- and 15-minute load averages ("a b c"), or "" when /proc/loadavg cannot be read.
std::string load_average();

/// scripts/plot_study.py of the source tree ($PBD_PLOT_SCRIPT overrides it).
std::filesystem::path plot_script();

/// Runs `/usr/bin/python3 plot_script() json dir` (Debian's python3 has python3-matplotlib); throws pbd::Error
/// if it fails.
void run_plot_script(const std::filesystem::path& json, const std::filesystem::path& dir);

}  // namespace pbd::cli
