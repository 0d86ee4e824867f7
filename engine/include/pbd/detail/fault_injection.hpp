#pragma once
// Fault injection (tests only, not host API: the engine's tests, pbd._inject_fault in Python, the io's frame writers):
// a test arms one fault, and the step throws it at the named phase, so the tests can check that every way a step can
// fail leaves the world as it was (World::step's undo, engine/src/step_undo.hpp) and every file complete.
// Unarmed, a fault point costs one relaxed atomic load; the points sit between a sub-step's phases, on the thread
// that runs the step (never inside a parallel loop or a team), so a fault leaves no thread behind.
#include <atomic>
#include <cstdint>

namespace pbd::detail {

/// Where a step can be made to fail: after each phase of a sub-step has run (so the state it changed is the state
/// the undo must put back), and in the frame writers (io).
enum class FaultPhase : std::uint8_t { predict, contacts, solve, update, step_end, frame_write, count };

/// What an armed fault throws.
enum class FaultKind : std::uint8_t { error, bad_alloc };

/// Arms one fault: the `hit`-th time (1: the first) a fault point of `phase` is reached, it throws `kind` (a
/// pbd::Error naming the phase, or std::bad_alloc) and disarms. Not thread-safe against a step running at the time.
void arm_fault(FaultPhase phase, FaultKind kind, int hit = 1);

/// Disarms the armed fault, if any; returns whether it had fired.
bool disarm_fault();

/// The phase's name ("predict", "contacts", "solve", "update", "step_end", "frame_write"), and the phase of a name
/// (FaultPhase::count for none).
const char* fault_phase_name(FaultPhase phase);
FaultPhase fault_phase_named(const char* name);

/// A fault point of `phase`: throws the armed fault when it is due there.
void fault_point_slow(FaultPhase phase);
extern std::atomic<bool> g_fault_armed;  // set between steps by the test; read by the thread running the step
inline void fault_point(FaultPhase phase) {
  if (__builtin_expect(g_fault_armed.load(std::memory_order_relaxed), false)) fault_point_slow(phase);
}

}  // namespace pbd::detail
