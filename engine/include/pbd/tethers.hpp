#pragma once
/// \file tethers.hpp
/// Generating long-range attachments (Kim, Chentanez and Müller 2012): for a body (a set of particles), every
/// movable particle gets a tether (constraints/tether.hpp) to the pinned or anchored particles of the body, so a
/// correction reaches the far end of a hanging cloth or rope in one sweep instead of one constraint per sweep.
///
/// The sources are the body's pinned particles (inverse mass 0; the tether's target is the pin's position and
/// follows it, tether.hpp) and its anchored particles (the target is the particle's first anchor's target, fixed).
/// Every other particle of the body with mass gets a tether to the nearest source, or one to each source. Its length
/// is the Euclidean distance from the particle to the target, or the geodesic one: the shortest path along the
/// body's stretch constraints (both ends in the body) by their rest lengths, plus the source's distance from its
/// target (Dijkstra; a particle no path reaches gets no tether). "Nearest" is by that length; ties go to the source
/// that comes first in the body's list. Every step is a function of the inputs alone (no hashing, no threads), so
/// World::add_tethers and pbd::io's DescriptionBuilder make the same tethers.
///
/// A body without a source gets no tether: there is nothing to hang from, and a scene that turns tethers on for
/// every body then works on free bodies too.
#include "pbd/constraints/anchor.hpp"
#include "pbd/constraints/stretch.hpp"
#include "pbd/constraints/tether.hpp"
#include "pbd/types.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace pbd {

/// Which sources a particle is tethered to.
enum class TetherTo : std::uint8_t {
  nearest,  ///< one tether, to the nearest source (one color: the tethers run in parallel over the particles)
  all,      ///< one tether to each source (one color per source)
};

/// How a tether's length is measured in the rest shape.
enum class TetherLength : std::uint8_t {
  euclidean,  ///< the straight distance to the target: tight for a body that is flat or straight at rest
  geodesic,   ///< along the stretch constraints' rest lengths: for a body folded or bent at rest
};

/// How World::add_tethers makes a body's tethers.
struct TetherOptions {
  TetherTo to = TetherTo::nearest;                ///< to the nearest source or to every one
  TetherLength length = TetherLength::euclidean;  ///< the rest length's measure
  double compliance = 0.0;                        ///< XPBD compliance α of their set, m/N, finite and ≥ 0 (0: rigid)
};

/// "nearest" or "all" as a TetherTo; nullopt for anything else.
std::optional<TetherTo> parse_tether_to(std::string_view name);
/// "euclidean" or "geodesic" as a TetherLength; nullopt for anything else.
std::optional<TetherLength> parse_tether_length(std::string_view name);

/// What a body's tethers are made from: the world's particles and constraints (anchors and stretch in insertion
/// order) in precision Real.
template <class Real> struct TetherInputs {
  std::span<const Index> body;                        ///< the body's particles, each once, all < num particles
  const Matrix3X<Real>* positions = nullptr;          ///< rest positions, 3×N
  const VectorX<Real>* inverse_masses = nullptr;      ///< N inverse masses (0 = pinned)
  std::span<const AnchorConstraint<Real>> anchors;    ///< every anchor (those on the body's particles are sources)
  std::span<const StretchConstraint<Real>> stretch;   ///< every stretch constraint (the geodesic graph's edges)
};

/// The tethers of one body (set `set`, pin = their source particle), in the order of the body's particles (then of
/// the sources); empty when the body has no source or no movable particle. `body` must hold valid indices, each
/// once (the caller checks them and names its call).
template <class Real>
std::vector<TetherConstraint<Real>> plan_tethers(const TetherInputs<Real>& in, const TetherOptions& options, Index set);

/// Throws "<fn>: ..." unless `body` names particles below n, each once, and options.compliance is finite and ≥ 0.
void check_tether_request(std::span<const Index> body, std::size_t n, const TetherOptions& options, const char* fn);

}  // namespace pbd
