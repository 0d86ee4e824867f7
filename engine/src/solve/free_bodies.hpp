#pragma once
// Free bodies (private): the rotation a solve must not add to a body that nothing outside it touches.  A body is a
// connected set of particles (joined by any built-in, user-defined or volume constraint). It is free in a sub-step
// when none of its particles is pinned or anchored and none has a contact: then only its own constraints act on it,
// and internal forces exert no net torque. A body whose contacts all push along one normal n (a body on the ground)
// is free about n: those forces have no torque about n, so it must keep its angular momentum about n. Gauss-Seidel
// breaks that where constraints cannot all hold: each projection is central about the positions it reads, not about
// the start of the sub-step, and a fixed order over conflicting constraints turns that into a steady spin (an over-
// constrained dodecahedron reaches 50 rad/s). So the velocity update (step 5 of solver.hpp) gives each free body
// back the angular momentum it had before the solve (after forces and damping): it removes the rigid rotation ω =
// I⁻¹ (L_after − L_before), L about the centre of mass (of p after, of x before) and I the inertia of p about its
// centre (for a body free about n only, the rotation about n: ω = n (n·ΔL) / (nᵀ I n)). It gives back the linear
// momentum as well (across n only), which the projections conserve up to rounding; in float that rounding adds up
// where conflicting constraints make large corrections every step. Every relative motion is untouched, and so are
// the positions. Bodies with pins or anchors are left as they are, and so are bodies with contacts along
// several normals: a torque from outside is real. A world without free bodies runs none of this.
#include "pbd/constraints/collision.hpp"
#include "pbd/constraints/particle_contact.hpp"
#include "pbd/detail/model.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace pbd::detail {

/// The spin's sums are taken over fixed chunks of particles (in parallel), then added in chunk order: the same bits
/// for any thread count.
inline constexpr Index kSpinChunk = 512;
inline constexpr int kSpinSums = 25;  // mass, Σ m p, Σ m x, Σ m p × v', Σ m x × v, Σ m v', Σ m v, Σ m p pᵀ (6)

/// A run of one body's particles within a chunk, and its sums.
struct SpinRun {
  Index body;
  std::array<double, kSpinSums> sums;
};

template <class Real> struct FreeBodies {
  std::uint64_t edits = ~std::uint64_t(0);  // Model::edits the bodies below were found at
  std::vector<Index> body;                  // per particle: its body, or kNone (no constraint, or held)
  Index count = 0;                          // bodies that may be free (no pinned particle, no anchor)
  std::vector<std::uint8_t> contact;        // per body, this sub-step: 0 no contact, 1 all along normal, 2 more
  std::vector<double> normal;               // per body with contact 1: that normal (3)
  std::vector<std::vector<SpinRun>> parts;  // per chunk of kSpinChunk particles: its runs of free bodies' particles
  std::vector<double> sums;                 // per body: mass and first and second moments (free_bodies.cpp)
  std::vector<double> omega;                // per body: ω to remove (3), centre of mass (3), velocity to remove (3);
                                            // NaN ω: leave the body alone
  static constexpr Index kNone = ~Index(0);
};

/// Finds the bodies again if the model changed since (Model::edits).
template <class Real> void update_free_bodies(const Model<Real>& m, FreeBodies<Real>& f);

/// The solver's spin is measured in three phases (step 5 of solver.hpp):
/// 1. find_free_contacts: this sub-step's contacts classify the bodies (a body with a particle contact, or a contact
///    with friction, is left alone); false (and nothing more to do) when no body is free. Sizes f.parts.
/// 2. sum_free_chunk, for every chunk (any order, any thread): the chunk's sums from x, the solved positions p and the
///    predicted velocities v.
/// 3. find_solver_spin: adds the chunks' sums in chunk order and sets f.omega; false when no body is to be despun.
template <class Real>
bool find_free_contacts(FreeBodies<Real>& f, std::span<const CollisionConstraint<Real>> contacts,
                        std::span<const ParticleContact<Real>> pairs);
template <class Real>
void sum_free_chunk(const Model<Real>& m, FreeBodies<Real>& f, Index chunk, const Real* x, const Real* p, const Real* v,
                    Real h);
template <class Real> bool find_solver_spin(FreeBodies<Real>& f);

}  // namespace pbd::detail
