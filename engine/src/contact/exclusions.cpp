// Phase 1 of the particle contacts (particle_contacts.hpp): the particles joined to one another by a built-in
// constraint, both in the same self-colliding body, which are never in contact. Rebuilt only when the model changed.
#include "phases.hpp"

#include "pbd/constraint_types.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>
#include <vector>

namespace pbd::detail::contact {

// Each particle's row lists all the particles joined to it (a candidate is tested against its row, whichever of the
// two is lower).
template <class Real> void build_exclusions(const Model<Real>& m, const Matrix3X<Real>& x, ParticleGrid<Real>& g) {
  const ContactBodies<Real>& c = m.contact;
  const Index n = m.num_particles();
  std::vector<std::pair<Index, Index>> pairs;
  auto self = [&](Index i) { return c.body_of[i] != ContactBodies<Real>::kNone && c.bodies[c.body_of[i]].self_collision; };
  for_each_store(m.stores, [&](const auto& st, auto) {
    for (const auto& con : st.items)
      for (std::size_t a = 0; a < con.particles.size(); ++a)
        for (std::size_t b = 0; b < con.particles.size(); ++b) {
          const Index u = con.particles[a], v = con.particles[b];
          if (u != v && self(u) && c.body_of[u] == c.body_of[v]) pairs.emplace_back(u, v);
        }
  });
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  // each row nearest first (at x; a non-finite distance last): the pairs found near are nearly always the nearest
  // joined ones (a cloth's edges), so the row's first groups decide them (joined_bits); the order changes only the cost
  std::vector<std::tuple<Index, Real, Index>> rows(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [u, v] = pairs[k];
    const Real gap = (x.col(u) - x.col(v)).squaredNorm();
    rows[k] = {u, std::isfinite(gap) ? gap : std::numeric_limits<Real>::infinity(), v};
  }
  std::sort(rows.begin(), rows.end());
  for (std::size_t k = 0; k < pairs.size(); ++k) pairs[k] = {std::get<0>(rows[k]), std::get<2>(rows[k])};
  // rows padded to whole groups of four with kNone (no particle), so that a row is compared four at a time
  g.joined_offsets.assign(std::size_t(n) + 1, 0);
  for (const auto& [u, v] : pairs) ++g.joined_offsets[u + 1];
  for (Index i = 0; i < n; ++i) g.joined_offsets[i + 1] = g.joined_offsets[i] + (g.joined_offsets[i + 1] + 3) / 4 * 4;
  g.joined.assign(g.joined_offsets[n], ContactBodies<Real>::kNone);
  std::vector<Index> fill(g.joined_offsets.begin(), g.joined_offsets.end() - 1);
  for (const auto& [u, v] : pairs) g.joined[fill[u]++] = v;
  g.joined_edits = m.edits;
  g.joined_bodies = c.bodies.size();
}

template void build_exclusions(const Model<float>&, const Matrix3X<float>&, ParticleGrid<float>&);
template void build_exclusions(const Model<double>&, const Matrix3X<double>&, ParticleGrid<double>&);

}  // namespace pbd::detail::contact
