#pragma once
// Where and when `pbd study` ran: machine, date, command line, build, and the commit it was built from. The commit
// is given to the program (`--commit`, $PBD_COMMIT; scripts/study passes `git describe`): the installed program
// knows no source tree to ask.
#include <nlohmann/json.hpp>

#include <string>

namespace pbd::cli {

/// {"pbd_version" (pbd/version.hpp), "command" (this process's argv from /proc/self/cmdline), "date" (UTC, ISO 8601),
/// "machine": {"nproc", "cpu", "host", "load_average_at_start"}, "git_commit" (`commit`, or "unknown" when it is
/// "")}; what cannot be found is null.
nlohmann::json study_environment(const std::string& commit);

/// The context block of a report, like Google Benchmark's: {"pbd_version", "compiler", "flags", "build_type", "cpu",
/// "cores", "host", "date", "commit", "loadavg_start"}, from `environment` (study_environment()) and the build; what
/// cannot be found is null.
nlohmann::json study_context(const nlohmann::json& environment);

}  // namespace pbd::cli
