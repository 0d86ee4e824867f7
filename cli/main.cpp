// pbd: command-line front end of the engine.
#include "commands.hpp"
#include "pbd/error.hpp"

#include <cstdio>
#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  CLI::App app{"pbd: data-parallel Position Based Dynamics"};
  app.require_subcommand(1);
  pbd::cli::add_study_command(app);
  pbd::cli::add_color_command(app);
  pbd::cli::add_run_command(app);
  pbd::cli::add_list_command(app);
  // A first word that is neither an option nor a subcommand is named (CLI11 alone says "A subcommand is required").
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      known = known || sub->check_name(argv[1]);
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::cerr << "pbd: error: unknown subcommand '" << argv[1] << "' (the subcommands: " << names << ")\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {  // pbd::Error, pbd::coloring::Error, I/O errors
    std::fflush(stdout);
    std::cerr << "pbd: error: " << e.what() << "\n";
    return 2;
  }
  // Whatever went to standard output must have arrived (a full disk, a closed pipe, /dev/full): a run whose report
  // was lost is a failure.
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::cerr << "pbd: error: cannot write to standard output (" << std::strerror(errno) << ")\n";
    return 2;
  }
  return 0;
}
