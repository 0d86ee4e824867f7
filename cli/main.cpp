// pbd: command-line front end of the engine.
//
// One convention for every way a command line can be wrong: a usage error (an unknown subcommand or option, a value
// out of range, an option that needs another) and a failure (a scene that does not parse, a write that fails) both
// print `pbd: error: ...` on stderr and exit with status 2; --help (on every subcommand) and --version print on
// stdout and exit 0. CLI11's own exit codes (105, 106, ...) and message style never reach the user. A run stopped by
// SIGINT or SIGTERM exits with 128 + the signal's number once its outputs are complete (stop_signals.hpp).
#include "commands.hpp"
#include "pbd/error.hpp"
#include "stop_signals.hpp"

#include <pbd/version.hpp>

#include <cstdio>
#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>

namespace {

constexpr int kUsageError = 2;

std::string subcommand_names(const CLI::App& app) {
  std::string names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names += (names.empty() ? "" : ", ") + sub->get_name();
  return names;
}

// "pbd study merge": the chain of subcommands the parser had reached, for the pointer to its --help.
std::string command_path(const CLI::App& app) {
  std::string path = app.get_name();
  for (const CLI::App* at = &app;;) {
    const std::vector<CLI::App*> chosen = at->get_subcommands();
    if (chosen.empty()) return path;
    at = chosen.front();
    path += " " + at->get_name();
  }
}

// CLI11's message, in pbd's style: its first letter lowered (CLI11 writes sentences; pbd's messages are clauses).
std::string usage_message(const CLI::App& app, const CLI::ParseError& e) {
  if (dynamic_cast<const CLI::RequiredError*>(&e) && app.get_subcommands().empty()) {
    std::string unknown;  // what came instead of a subcommand (an option pbd does not have)
    for (const std::string& arg : app.remaining()) unknown += (unknown.empty() ? "" : " ") + arg;
    return (unknown.empty() ? "" : "'" + unknown + "' is not an option of pbd; ") +
           "a subcommand is required (the subcommands: " + subcommand_names(app) + ")";
  }
  std::string text = e.what();
  if (!text.empty() && text[0] >= 'A' && text[0] <= 'Z' && (text.size() < 2 || text[1] < 'A' || text[1] > 'Z'))
    text[0] = char(text[0] - 'A' + 'a');
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pbd: data-parallel Position Based Dynamics"};
  app.name("pbd");
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("pbd ") + PBD_VERSION_STRING, "Print pbd's version and exit");
  pbd::cli::add_study_command(app);
  pbd::cli::add_color_command(app);
  pbd::cli::add_run_command(app);
  pbd::cli::add_list_command(app);
  // A first word that is neither an option nor a subcommand is named (CLI11 alone says "A subcommand is required").
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      known = known || sub->check_name(argv[1]);
    if (!known) {
      std::cerr << "pbd: error: unknown subcommand '" << argv[1] << "' (the subcommands: " << subcommand_names(app)
                << ")\n";
      return kUsageError;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version: printed on stdout, status 0
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "pbd: error: " << usage_message(app, e) << " (see `" << command_path(app) << " --help`)\n";
    return kUsageError;
  } catch (const pbd::cli::Interrupted& e) {
    std::fflush(stdout);
    std::cerr << "pbd: " << e.what() << "\n";
    return 128 + e.signal;
  } catch (const std::exception& e) {  // pbd::Error, pbd::coloring::Error, I/O errors
    std::fflush(stdout);
    std::cerr << "pbd: error: " << e.what() << "\n";
    return kUsageError;
  }
  // Whatever went to standard output must have arrived (a full disk, a closed pipe, /dev/full): a run whose report
  // was lost is a failure.
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::cerr << "pbd: error: cannot write to standard output (" << std::strerror(errno) << ")\n";
    return kUsageError;
  }
  return 0;
}
