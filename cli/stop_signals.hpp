#pragma once
// SIGINT and SIGTERM during `pbd run`: the run stops after the step (and its frame) under way, completes its outputs
// and exits with status 128 + the signal's number (130, 143), as a shell reports a process the signal ended.
#include <stdexcept>
#include <string>

namespace pbd::cli {

/// Handlers for SIGINT and SIGTERM for the lifetime of the object (the previous ones are restored after). A signal
/// only sets a flag (all a handler may safely do); the handler then resets itself, so that a second signal ends the
/// process at once, as if pbd had none (an impatient second Ctrl-C during a long step).
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  /// The signal received (SIGINT or SIGTERM), or 0.
  int received() const;
};

/// Thrown once a run stopped by a signal has completed its outputs: main() prints the message and exits with
/// 128 + signal.
struct Interrupted : std::runtime_error {
  Interrupted(int number, const std::string& what) : std::runtime_error(what), signal(number) {}
  int signal;
};

}  // namespace pbd::cli
