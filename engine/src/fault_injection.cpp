// Fault injection (fault_injection.hpp): one armed fault at a time.
#include "pbd/detail/fault_injection.hpp"

#include "pbd/error.hpp"

#include <cstring>
#include <new>
#include <string>

namespace pbd::detail {

std::atomic<bool> g_fault_armed{false};

namespace {
FaultPhase armed_phase = FaultPhase::count;
FaultKind armed_kind = FaultKind::error;
int hits_left = 0;
bool fired = false;
constexpr const char* kNames[] = {"predict", "contacts", "solve", "update", "step_end", "frame_write"};
static_assert(std::size(kNames) == std::size_t(FaultPhase::count));
}  // namespace

void arm_fault(FaultPhase phase, FaultKind kind, int hit) {
  armed_phase = phase;
  armed_kind = kind;
  hits_left = hit < 1 ? 1 : hit;
  fired = false;
  g_fault_armed.store(true);
}

bool disarm_fault() {
  g_fault_armed.store(false);
  armed_phase = FaultPhase::count;
  return fired;
}

const char* fault_phase_name(FaultPhase phase) {
  return phase < FaultPhase::count ? kNames[std::size_t(phase)] : "none";
}

FaultPhase fault_phase_named(const char* name) {
  for (std::size_t i = 0; i < std::size(kNames); ++i)
    if (std::strcmp(kNames[i], name) == 0) return FaultPhase(i);
  return FaultPhase::count;
}

void fault_point_slow(FaultPhase phase) {
  if (phase != armed_phase || --hits_left > 0) return;
  g_fault_armed.store(false);
  fired = true;
  if (armed_kind == FaultKind::bad_alloc) throw std::bad_alloc();
  throw Error(std::string("injected fault at ") + fault_phase_name(phase));
}

}  // namespace pbd::detail
