// pbd: command-line front end of the engine.
#include "commands.hpp"
#include "pbd/error.hpp"

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"pbd: data-parallel Position Based Dynamics"};
  app.require_subcommand(1);
  pbd::cli::add_study_command(app);
  pbd::cli::add_color_command(app);
  pbd::cli::add_run_command(app);
  pbd::cli::add_list_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {  // pbd::Error, pbd::coloring::Error, I/O errors
    std::cerr << "pbd: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
