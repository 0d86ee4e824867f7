#pragma once
// The owner of the padded copy of the positions during a sub-step's sweeps (private). The SIMD kernels project on x
// y z w per particle (w the inverse mass, Scratch::padded: one aligned load and store per particle); everything else
// reads and writes p (3 per particle). This class knows which of the two holds the current positions and copies
// between them only when the next reader needs the other one:
//   to_padded()  before a kernel: copies p and w in, unless the copy is current
//   to_p()       before anything that reads p (a type without a kernel, user types, volumes, contacts, the end of
//                the sub-step): copies the positions back, unless p is current
//   end_sweep()  under Keep::per_sweep, p holds the positions after every sweep; under Keep::substep (every type
//                the sweeps project runs on the copy) they stay in the copy from sweep to sweep until end().
// A caller that writes the copy itself (the prediction, solver.hpp) hands it over with adopt(). Each member of a
// team holds its own PaddedPositions and takes the same path, so the copies are the team's loops.
#include "sweep_loops.hpp"
#include "bending_kernel.hpp"  // pad_positions (double)
#include "stretch_kernel.hpp"  // pad_positions (float)

#include <cassert>

namespace pbd::detail {

template <class Real> class PaddedPositions {
public:
  /// When the positions go back to p: after every sweep, or only at the sub-step's end.
  enum class Keep { per_sweep, substep };

  PaddedPositions(Scratch<Real>& scratch, Index particles, Keep keep) : k_(&scratch), n_(particles), keep_(keep) {}

  /// The sweeps keep the positions in the copy from the first sweep to end() (a caller may then write the copy
  /// itself, adopt(), and read the result from it).
  bool kept() const { return keep_ == Keep::substep && k_->padded.size() == n_; }
  /// The copy holds the current positions (p is stale).
  bool current() const { return where_ == Where::padded; }
  /// The caller wrote every particle's position and inverse mass into the copy (kept()).
  void adopt() {
    assert(kept());
    where_ = Where::padded;
  }

  /// Reserves this sweep's partitioner slots of the two copies (every sweep reserves them, used or not).
  void start_sweep(SweepLoops<Real>& loops) {
    pad_slot_ = loops.slots(1);
    unpad_slot_ = loops.slots(1);
  }
  /// The copy, made current from p and the inverse masses w.
  Real* to_padded(SweepLoops<Real>& loops, const Real* p, const Real* w) {
    Real* q = k_->padded.data();
    if (where_ == Where::padded) return q;
    assert(k_->padded.size() == n_);  // sized by Sweeper::begin
    loops.range(0, n_, loops.config(), pad_slot_, [&](Index b, Index e) { pad_positions(p, w, b, e, q); });
    where_ = Where::padded;
    return q;
  }
  /// p made current.
  void to_p(SweepLoops<Real>& loops, Real* p) {
    if (where_ == Where::p) return;
    const Real* q = k_->padded.data();
    loops.range(0, n_, loops.config(), unpad_slot_, [&](Index b, Index e) { unpad_positions(q, b, e, p); });
    where_ = Where::p;
  }
  /// The end of a sweep: p made current unless the copy is kept.
  void end_sweep(SweepLoops<Real>& loops, Real* p) {
    if (keep_ == Keep::per_sweep) to_p(loops, p);
  }

private:
  enum class Where { p, padded };  // which holds the current positions
  Scratch<Real>* k_;
  Index n_;
  Keep keep_;
  Where where_ = Where::p;
  std::size_t pad_slot_ = 0, unpad_slot_ = 0;
};

}  // namespace pbd::detail
