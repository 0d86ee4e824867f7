#include "stop_signals.hpp"

#include <csignal>
#include <utility>

namespace pbd::cli {
namespace {

volatile std::sig_atomic_t g_received = 0;
struct sigaction g_previous_int, g_previous_term;

extern "C" void on_stop_signal(int number) { g_received = number; }

}  // namespace

StopSignals::StopSignals() {
  g_received = 0;
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;  // no SA_RESTART: the writes retry on EINTR themselves
  // A signal the caller ignores stays ignored (nohup, a shell's background job): it was not meant to stop pbd.
  for (auto [number, previous] : {std::pair{SIGINT, &g_previous_int}, std::pair{SIGTERM, &g_previous_term}}) {
    sigaction(number, nullptr, previous);
    if (previous->sa_handler != SIG_IGN) sigaction(number, &action, nullptr);
  }
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

int StopSignals::received() const { return g_received; }

}  // namespace pbd::cli
