#pragma once
// The rules between options: an option that does nothing without another one, or next to another one, is refused
// (a usage error: `pbd: error: ...`, status 2) rather than silently ignored. Only what the command line gave counts
// (CLI::Option::count): defaults and environment variables are not the user asking for something.
#include "pbd/error.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace pbd::cli {

/// Whether `option` was given on the command line of `cmd`.
inline bool given(const CLI::App& cmd, const std::string& option) { return cmd.count(option) > 0; }

/// Refuses `option` given without `needed`: "--format does nothing without --frames (why)".
inline void refuse_without(const CLI::App& cmd, const std::string& option, const std::string& needed,
                           const std::string& why) {
  if (given(cmd, option) && !given(cmd, needed))
    throw Error(option + " does nothing without " + needed + " (" + why + ")");
}

/// Refuses `option` when `condition` holds: "--sweep-order does nothing with <what> (why)".
inline void refuse_with(const CLI::App& cmd, const std::string& option, bool condition, const std::string& what,
                        const std::string& why) {
  if (given(cmd, option) && condition) throw Error(option + " does nothing with " + what + " (" + why + ")");
}

/// Refuses an option given an empty value (`--budgets ''`): to the command an empty value is the option not given,
/// so its default would run in silence. Flags take no value and are not concerned.
inline void refuse_empty_values(const CLI::App& cmd) {
  for (const CLI::Option* option : cmd.get_options())
    if (option->get_type_size_max() > 0)
      for (const std::string& value : option->results())
        if (value.empty())
          throw Error(option->get_name() + ": the value is empty (give one, or leave the option out for its "
                      "default)");
}

}  // namespace pbd::cli
