#include "plot_script.hpp"

#include "pbd/error.hpp"

#include <cerrno>
#include <cstdio>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <vector>

extern char** environ;

namespace pbd::cli {
namespace {

std::filesystem::path script_of(const PlotTools& tools) {
  const bool given = !tools.script.empty();
  const std::filesystem::path script = given ? std::filesystem::path(tools.script) : tools.default_script;
  std::error_code ec;
  if (!script.empty() && std::filesystem::is_regular_file(script, ec)) return script;
  throw Error("--plots: the plot script \"" + script.string() + "\" (" +
              (given ? "--plot-script or PBD_PLOT_SCRIPT" : "share/pbd/plot_study.py beside the program") +
              ") is not a file; give --plot-script FILE or set PBD_PLOT_SCRIPT");
}

constexpr int kCannotStart = -1;
constexpr int kNoExitStatus = -2;  // ended by a signal, or the wait failed

// Runs argv (argv[0] looked up on PATH when it has no '/') and waits: its exit status, kCannotStart or kNoExitStatus.
// No shell: the paths need no quoting. `quiet`: its stderr goes to /dev/null (a probe whose failure pbd explains).
int run(const std::vector<std::string>& args, bool quiet = false) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return kCannotStart;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return kNoExitStatus;
  return WIFEXITED(status) ? WEXITSTATUS(status) : kNoExitStatus;
}

}  // namespace

void check_plot_tools(const PlotTools& tools) {
  (void)script_of(tools);
  std::fflush(stdout);
  std::fflush(stderr);
  const int status = run({tools.python, "-c", "import matplotlib"}, true);
  if (status == 0) return;
  if (status == kCannotStart)
    throw Error("--plots: cannot start the interpreter \"" + tools.python + "\" (--python or PBD_PYTHON names it; "
                "default: python3 on PATH)");
  throw Error("--plots: the interpreter \"" + tools.python + "\" cannot import matplotlib (e.g. Debian's "
              "python3-matplotlib; --python or PBD_PYTHON chooses the interpreter)");
}

void run_plot_script(const PlotTools& tools, const std::filesystem::path& json, const std::filesystem::path& dir) {
  const std::vector<std::string> args = {tools.python, script_of(tools).string(), json.string(), dir.string()};
  std::fflush(stdout);
  std::fflush(stderr);
  const int status = run(args);
  if (status == 0) return;
  if (status == kCannotStart)
    throw Error("--plots: cannot start the interpreter \"" + tools.python + "\" (--python or PBD_PYTHON names it; "
                "default: python3 on PATH)");
  std::string command;
  for (const std::string& a : args) command += (command.empty() ? "" : " ") + a;
  throw Error("--plots: `" + command + "` failed (the script needs matplotlib, e.g. Debian's python3-matplotlib; "
              "--python or PBD_PYTHON chooses the interpreter)");
}

}  // namespace pbd::cli
