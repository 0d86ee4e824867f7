#include "schedule.hpp"

#include "pbd/detail/block_layout.hpp"
#include "kernel_table.hpp"

#include <pbd/graph_coloring/partition.hpp>

#include <algorithm>
#include <cassert>

namespace pbd::detail {
namespace {

// Jacobi counts from scratch: built-in and user-defined constraints touching each particle (not the volumes, which
// Jacobi projects in place, sweep.hpp).
template <class Real> void count_touches(Model<Real>& m) {
  m.touch_count.assign(m.num_particles(), 0);
  for_each_type(m, [&](const TypeStore<Real>& type, std::size_t) { type.count_particles(m.touch_count, 0); });
}

// Model::color_sets of the types whose kernel reads them, colors from each one's `first(type)` on.
template <class Real, class First> void note_color_sets(Model<Real>& m, const First& first) {
  m.color_sets.resize(m.num_types());
  for_each_type(m, [&](const TypeStore<Real>& type, std::size_t t) {
    if (padded_kernel<Real>(t).color_sets) type.note_color_sets(m.color_sets[t], first(type), kMixedSets);
    else m.color_sets[t].clear();
  });
}
template <class Real> void note_color_sets(Model<Real>& m) {
  note_color_sets(m, [](const TypeStore<Real>&) { return Index(0); });
}

// Model::particle_cuts of every type (colors layout; cleared under the block layout, whose members cut by block).
// O(constraints), after every change of layout.
template <class Real> void note_particle_cuts(Model<Real>& m) {
  m.particle_cuts.resize(m.num_types());
  for_each_type(m, [&](const TypeStore<Real>& type, std::size_t t) {
    if (m.layout == Layout::colors) type.note_particle_cuts(m.particle_cuts[t], m.num_particles(), kCutParts);
    else m.particle_cuts[t].clear();
  });
}

// Volume constraints colored on their particles (a volume on more than wide_threshold particles gets a color of its
// own, and runs alone with parallelism inside it).
template <class Real> void color_volumes(Model<Real>& m) {
  auto& v = m.volume;
  v.order.clear();
  v.offsets.clear();
  const auto& t = v.table;
  if (t.empty()) return;
  ConstraintGraph g;
  g.num_particles = m.num_particles();
  g.fixed = m.fixed;
  g.offsets.push_back(0);
  for (const auto& c : t.items) {
    g.nodes.insert(g.nodes.end(), t.particles.begin() + c.row_begin, t.particles.begin() + c.row_end);
    g.offsets.push_back(std::uint32_t(g.nodes.size()));
  }
  coloring::Coloring col;
  try {
    col = coloring::color(g.view(), m.coloring);
  } catch (const coloring::Error& e) {
    throw Error(std::string("coloring volume constraints: ") + e.what());
  }
  v.order.assign(col.items.begin(), col.items.end());
  v.offsets.assign(col.color_offsets.begin(), col.color_offsets.end());
}

// Splits the particles into blocks of about BlockOptions::constraints_per_block built-in and user constraints each
// (graph_coloring::partition over the particles the constraints join; volumes and contacts are not blocked).
template <class Real> void partition_particles(Model<Real>& m) {
  ConstraintGraph g;
  g.num_particles = std::uint32_t(m.num_particles());
  g.fixed = m.fixed;
  g.offsets.push_back(0);
  std::size_t constraints = 0;
  for_each_type(m, [&](const TypeStore<Real>& type, std::size_t) { constraints += type.add_to_partition_graph(g); });
  const std::size_t per = std::max<std::size_t>(1, m.blocking.constraints_per_block);
  coloring::PartitionOptions o;
  o.method = m.blocking.use_metis ? coloring::PartitionMethod::metis : coloring::PartitionMethod::index_ranges;
  o.parts = std::uint32_t(std::max<std::size_t>(1, (constraints + per / 2) / per));
  coloring::Partition part;
  try {
    part = coloring::partition(g.view(), o);
  } catch (const coloring::Error& e) {
    throw Error(std::string("partitioning the particles into blocks: ") + e.what());
  }
  m.block = std::move(part.block);
  m.num_blocks = Index(std::max<std::uint32_t>(1, part.parts));
}

// Every store laid out for the block schedule on the current partition (only the boundary constraints are colored).
template <class Real> void lay_out_all_blocks(Model<Real>& m) {
  for_each_type(m, [&](TypeStore<Real>& type, std::size_t) { type.lay_out_blocks(m.fixed, m.block, m.num_blocks, m.coloring); });
}

}  // namespace

template <class Real> std::vector<std::uint8_t> pinned_flags(const VectorX<Real>& w) {
  std::vector<std::uint8_t> fixed(std::size_t(w.size()));
  for (Eigen::Index i = 0; i < w.size(); ++i) fixed[std::size_t(i)] = w[i] == Real(0);
  return fixed;
}

template <class Real> void color_everything(Model<Real>& m) {
  m.fixed = pinned_flags(m.inverse_mass);
  if (m.layout == Layout::blocks) {
    partition_particles(m);
    lay_out_all_blocks(m);
  } else {
    m.block.clear();
    m.num_blocks = 0;
    for_each_type(m, [&](TypeStore<Real>& type, std::size_t) { type.color_all(m.fixed, m.coloring); });
  }
  color_volumes(m);
  count_touches(m);
  note_color_sets(m);
  note_particle_cuts(m);
  m.colors_current = true;
}

template <class Real> void update_colors(Model<Real>& m, Layout layout) {
  if (m.layout != layout) {
    m.layout = layout;
    m.colors_current = false;
  }
  if (!m.colors_current) return color_everything(m);
  const Index n = m.num_particles();
  for (Index i = Index(m.fixed.size()); i < n; ++i) m.fixed.push_back(m.inverse_mass[i] == Real(0));  // added ones
  m.touch_count.resize(n, 0);  // particles added since: nothing touches them yet
  if (layout == Layout::blocks) {
    // Particles added since the partition are in no block, so their constraints cross blocks: partition anew once
    // they are more than a tenth. Otherwise a store with new constraints is laid out again on the same blocks,
    // which colors only its boundary constraints.
    if (std::size_t(n) - m.block.size() > m.block.size() / 10) return color_everything(m);
    bool changed = false;
    for_each_type(m, [&](TypeStore<Real>& type, std::size_t) {
      if (type.up_to_date()) return;
      type.lay_out_blocks(m.fixed, m.block, m.num_blocks, m.coloring);
      changed = true;
    });
    if (m.volume.offsets.empty() != m.volume.table.empty() || m.volume.order.size() != m.volume.table.size()) {
      color_volumes(m);
      changed = true;
    }
    if (changed) note_layout(m);
    return;
  }
  // Only the appended constraints are colored (tail colors), and only they are added to the Jacobi counts.
  bool ok = true, stores_changed = false;
  for_each_type(m, [&](TypeStore<Real>& type, std::size_t) {
    if (!ok || type.up_to_date()) return;
    const Index first = type.first_uncolored();
    stores_changed = true;
    ok = type.color_tail(m.fixed);
    if (ok) type.count_particles(m.touch_count, first);
  });
  if (!ok) return color_everything(m);
  bool volumes_changed = false;
  if (m.volume.offsets.empty() != m.volume.table.empty() || m.volume.order.size() != m.volume.table.size()) {
    color_volumes(m);
    volumes_changed = true;
  }
  if (volumes_changed) {
    count_touches(m);
    note_color_sets(m);
  } else {  // appended constraints changed only the tail colors (they may have joined a color of another set)
    note_color_sets(m, [](const TypeStore<Real>& type) { return std::min(type.tail_color(), type.num_colors()); });
  }
  if (stores_changed) note_particle_cuts(m);
}

template <class Real> void note_layout(Model<Real>& m) {
  count_touches(m);
  note_color_sets(m);
  note_particle_cuts(m);
}

namespace {

// First fit in generation order (the lowest color free at each item's non-pinned particles) of the items of `g`,
// then `s` laid out color by color; w's buffers are kept from sub-step to sub-step, so nothing is allocated once
// they have grown. More than 64 colors (never seen on contacts) take graph_coloring's first fit, which has no limit.
template <class C> void first_fit_layout(Store<C>& s, const ConstraintGraph& g, FirstFitScratch<C>& w) {
  const coloring::Hypergraph view = g.view();
  w.used.assign(g.num_particles, 0);
  w.color.resize(s.items.size());
  if (!coloring::first_fit_extend(view, w.used, 64, w.color)) {
    coloring::Options first_fit;
    first_fit.algorithm = coloring::Algorithm::greedy_input;
    first_fit.balance = false;
    const coloring::Coloring col = coloring::color(view, first_fit);
    w.color.assign(col.color.begin(), col.color.end());
  }
  w.by_index.swap(s.items);  // s.items keeps the other buffer: layout_by_color overwrites it
  s.color.assign(w.color.begin(), w.color.end());
  layout_by_color(s, w.by_index);
}

}  // namespace

template <class Real>
void color_collisions(Store<CollisionConstraint<Real>>& s, FirstFitScratch<CollisionConstraint<Real>>& w) {
  assert(s.slot.empty() && s.color.empty());
  const Index n = Index(s.size());
  if (n == 0) return;
  // Collisions arrive particle by particle: number the distinct particles so the graph has as many nodes as there
  // are colliding particles, not as the world has particles. The k-th collision of a particle gets color k.
  ConstraintGraph& g = w.graph;
  g.fixed = {};
  g.offsets.resize(std::size_t(n) + 1);
  for (Index i = 0; i <= n; ++i) g.offsets[i] = std::uint32_t(i);
  g.nodes.resize(n);
  std::uint32_t node = 0;
  for (Index i = 0; i < n; ++i) {
    if (i > 0 && s.items[i].particles[0] != s.items[i - 1].particles[0]) ++node;
    g.nodes[i] = node;
  }
  g.num_particles = node + 1;
  first_fit_layout(s, g, w);
}

template <class Real>
void color_particle_contacts(Store<ParticleContact<Real>>& s, const std::vector<std::uint8_t>& fixed,
                             FirstFitScratch<ParticleContact<Real>>& w) {
  assert(s.slot.empty() && s.color.empty());
  if (s.empty()) return;
  fill_constraint_graph(std::span<const ParticleContact<Real>>(s.items), fixed, w.graph);
  first_fit_layout(s, w.graph, w);
}

#define PBD_SCHEDULE_INSTANTIATE(Real)                                                  \
  template std::vector<std::uint8_t> pinned_flags(const VectorX<Real>&);                \
  template void color_everything(Model<Real>&);                                         \
  template void update_colors(Model<Real>&, Layout);                                            \
  template void note_layout(Model<Real>&);                                              \
  template void color_collisions(Store<CollisionConstraint<Real>>&, FirstFitScratch<CollisionConstraint<Real>>&); \
  template void color_particle_contacts(Store<ParticleContact<Real>>&, const std::vector<std::uint8_t>&,          \
                                        FirstFitScratch<ParticleContact<Real>>&);
PBD_SCHEDULE_INSTANTIATE(float)
PBD_SCHEDULE_INSTANTIATE(double)
#undef PBD_SCHEDULE_INSTANTIATE

}  // namespace pbd::detail
