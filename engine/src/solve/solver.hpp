#pragma once
// The solver (private): what World::step() runs, in what order, what runs in parallel, and why.
//
// A step of length dt is `substeps` sub-steps of h = dt / substeps (Small Steps, Macklin et al. 2019: the error
// falls with h², so n sub-steps of one sweep beat one step of n sweeps). Before the first sub-step, the colored
// and Jacobi solvers bring the colors up to date (schedule.hpp: only constraints added since the last step are
// colored, into tail colors; everything is recolored after pins change, a particle is removed or the coloring
// options change), and every tether whose pin is pinned takes the pin's position as its target (tether.hpp: a host
// may move pins between steps). Each sub-step then runs, in order:
//   1. damping and forces   v ← v·max(0, 1 − damping·h), then v += h·(g + w·f); a pinned particle keeps its v
//                           (0 unless a host or a scene's grip set one: it then moves at it, a kinematic grip)
//                           (damping first: a body at rest under gravity then sags by the whole of g)
//   2. predict              p = x + h·v
//   3. contacts             one inequality per (movable particle, collider) whose path x → p enters the collider or
//                           ends within the margin (colliders.hpp; a contact body's particle by its radius), and,
//                           when a contact body has a radius, one per pair of particles whose relative path comes
//                           within their radii and the margin (contact/particle_contacts.hpp: a grid of swept
//                           boxes); each records its material and approach speed; colored for the colored solvers.
//                           A parallel solver generates the two kinds at once (apart outputs): the colliders' chunks
//                           fill the other threads while the broad phase runs its serial passes. Then a
//                           particle whose x is already behind a collider's surface moves out to it, x and p alike
//                           (contact/prestabilize.hpp: a push the solve made would stay in v = (p − x)/h as speed)
//   4. solve                `iterations` sweeps (sweep.hpp): each visits every constraint type through one loop
//                           (for_each_type: the built-in types in list order, constraint_types.hpp, then the
//                           user-defined ones in the order first added), then the volume constraints, then the
//                           contacts (the block solver: every type's block interiors first, then the rest as
//                           colored); a type with a SIMD kernel (kernels.hpp) runs it where it serves the schedule;
//                           a contact's projection ends with its friction (Macklin et al. 2014 §6.1);
//                           with Chebyshev acceleration, each sweep's result is extrapolated (chebyshev.hpp; a
//                           measured ρ is kept in the State, an output, never in the user's parameters);
//                           with SweepOrder::symmetric, odd sub-steps visit each type backwards (the sub-step's
//                           number is round(time / dt) · substeps + s: a function of the world's time, so a copy
//                           made at any step, or a world whose time was set, sweeps the same way).
//                           A fiber in a set with a stress–strain curve is projected by its force law (material.hpp:
//                           XPBD with the tangent compliance, so λ converges to −h²·F and a slack fiber returns its λ)
//   4b. plastic flow        each fiber of a yielding set whose force at p is above its yield force gets the
//                           plastic strain that puts it back on it (engine/src/fibers.hpp; each on its own, so the
//                           order changes no bit). A step with plastic flow forks per loop (no team for its sub-steps)
//   5. update               v = (p − x) / h, x = p; computed as v += (p − p̂)/h (p̂ = x + h·v, the prediction), so a
//                           velocity no constraint changed keeps every digit (in float, v = (p − x)/h rounds to
//                           multiples of ulp(x)/h, and a slow body whose damping is under half of that never
//                           stops). A free body (no pin, anchor or contact, or contacts along one normal only) gets
//                           back the momentum and angular momentum the solve changed (free_bodies.hpp): internal
//                           forces exert none, but Gauss-Seidel over constraints that cannot all hold spun such a
//                           body up (a body with a particle contact or friction is not free). Last, restitution:
//                           a touched contact of e > 0 leaves at e × its approach speed (restitution.hpp).
// Steps 1, 2 and 5 are per particle and run as parallel loops for the parallel solvers (the free bodies' sums in
// step 5 over fixed chunks of particles, added in chunk order, so they give the same bits on any thread count). In
// step 4 the colored solver runs each color as a parallel loop: a color's constraints write no particle twice, so the
// result is the serial color-order result bit for bit, whatever the thread count (pinned particles are never written,
// so they never conflict). A volume constraint spans a mesh: its sums are reduced over fixed blocks in block order, so it
// too gives the same bits on any thread count. Colors smaller than ParallelConfig::inline_below run inline: a
// fork/join costs about as much as projecting a thousand constraints. The Gauss-Seidel sweeps of the colored and
// block solvers hold one team of threads for the whole solve instead (team.hpp: a barrier per loop, a fork/join per
// sub-step). Steps 1–5 are one function (engine/src/substep.cpp) run on one of two runners, chosen in one place
// (run_substeps): a step that is only steps 1, 2, 4 and 5 (no collider, force callback or free body) holds one team
// for all its sub-steps, steps 1–2 and 5 being the team's loops over the particles; any other step forks per loop.
// The team's wait for its workers is retuned after each team in one place (retune_team). After the last sub-step,
// every fiber whose total strain has reached its set's rupture strain breaks (World::last_breaks): all are judged on
// the step's final positions, so which break depends neither on their order nor on the thread count, and they leave
// the model as remove_constraints removes (the others keep their colors; λ moves with them, so the forces read after
// the step stay right). The tets holding both ends of a broken fiber break with it (engine/src/tear_cells.hpp). Then
// each surface that tears (World::add_surface) is cut along them and the particles each cut separates are copied
// (engine/src/tear.hpp), the other constraints keeping their colors. Everything runs in
// the caller's tbb::task_arena, so a host decides the thread count.
#include "pbd/step_params.hpp"
#include "pbd/detail/model.hpp"
#include "scratch.hpp"

#include <chrono>
#include <functional>

namespace pbd::detail {

/// What a sub-step's solve reports.
struct SolveReport {
  bool chebyshev_fell_back = false;  ///< the Chebyshev guard stopped the acceleration
  int threads = 1;                   ///< threads that ran the sweeps together (a team, team.hpp; 1: none)
  double wait_fraction = 0.0;        ///< share of those threads' time spent waiting for one another (barriers)
};

/// Step 4 of a sub-step: λ reset where needed, `params.iterations` sweeps of `params.solver` on scratch.p, at time
/// `time` (s, for volume targets); `reverse`: each type backwards (SweepOrder::symmetric, odd sub-step). The
/// collisions in scratch.collisions are those of this sub-step, in generation order; colored solvers lay them out by
/// color first. The colors must be up to date (update_colors). Chebyshev acceleration with ρ = 0 uses the ρ a
/// sub-step measured before (State::chebyshev_rho), or measures it and keeps it there.
template <class Real>
SolveReport solve(Model<Real>& model, State<Real>& state, Scratch<Real>& scratch, const StepParams<Real>& params,
           const ParallelConfig& config, double time, bool reverse);

/// After a team ran (took: how long; members: how many threads joined): how long the next team waits for its
/// workers, and how many solves fork instead after teams that no worker joined.
template <class Real> void retune_team(Scratch<Real>& scratch, std::chrono::steady_clock::duration took, int members);

}  // namespace pbd::detail
