#pragma once
/// \file constraint_graph.hpp
/// The conflict hypergraph of one constraint array, as graph_coloring takes it: items = constraints,
/// nodes = particles, pinned particles (inverse mass 0) fixed because no projection ever writes them.
#include "pbd/types.hpp"

#include <pbd/graph_coloring/hypergraph.hpp>

#include <vector>

namespace pbd {

/// Owning CSR storage of a constraint hypergraph; view() is what graph_coloring reads.
struct ConstraintGraph {
  std::vector<std::uint32_t> offsets;  ///< constraints + 1 entries
  std::vector<std::uint32_t> nodes;    ///< particles of each constraint, constraint after constraint
  std::vector<std::uint8_t> fixed;     ///< 1 for pinned particles
  std::uint32_t num_particles = 0;     ///< number of particles

  /// Non-owning view for graph_coloring (valid while this object lives).
  coloring::Hypergraph view() const { return {offsets, nodes, num_particles, fixed}; }
};

/// Flags of the particles whose inverse mass is 0.
template <class Real> std::vector<std::uint8_t> pinned_flags(const VectorX<Real>& inverse_masses) {
  std::vector<std::uint8_t> fixed(std::size_t(inverse_masses.size()));
  for (Eigen::Index i = 0; i < inverse_masses.size(); ++i) fixed[std::size_t(i)] = inverse_masses[i] == Real(0);
  return fixed;
}

/// The hypergraph of an array of fixed-arity constraints (each has `particles`).
template <class Constraint>
ConstraintGraph constraint_graph(const std::vector<Constraint>& items, std::vector<std::uint8_t> fixed) {
  ConstraintGraph g;
  g.num_particles = std::uint32_t(fixed.size());
  g.fixed = std::move(fixed);
  g.offsets.reserve(items.size() + 1);
  g.offsets.push_back(0);
  g.nodes.reserve(items.size() * Constraint::kArity);
  for (const Constraint& c : items) {
    for (Index p : c.particles) g.nodes.push_back(p);
    g.offsets.push_back(std::uint32_t(g.nodes.size()));
  }
  return g;
}

}  // namespace pbd
