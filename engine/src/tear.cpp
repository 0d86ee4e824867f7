// Tearing surfaces along broken fibers (tear.hpp).
#include "tear.hpp"

#include "solve/schedule.hpp"

#include <algorithm>
#include <numeric>

namespace pbd::detail {
namespace {

using Edge = std::array<Index, 2>;
Edge edge(Index a, Index b) { return a < b ? Edge{a, b} : Edge{b, a}; }

bool holds(const std::array<Index, 3>& t, Index p) { return t[0] == p || t[1] == p || t[2] == p; }

// Per particle, the triangles of `s` holding it (CSR: triangles[offset[p], offset[p + 1])), for particles < n.
struct Incidence {
  std::vector<Index> offset, triangles;
  Incidence(const Surface& s, Index n) : offset(std::size_t(n) + 1, 0) {
    for (const auto& t : s.triangles)
      for (Index p : t) ++offset[p + 1];
    std::partial_sum(offset.begin(), offset.end(), offset.begin());
    triangles.resize(offset.back());
    std::vector<Index> next(offset.begin(), offset.end() - 1);
    for (Index k = 0; k < Index(s.triangles.size()); ++k)
      for (Index p : s.triangles[k]) triangles[next[p]++] = k;
  }
  std::span<const Index> of(Index p) const { return {triangles.data() + offset[p], triangles.data() + offset[p + 1]}; }
};

// The groups of the fan `fan` (triangles holding v, ascending) joined across uncut shared edges (v, u): each
// triangle's group, numbered in order of the groups' lowest triangles.
std::vector<Index> fan_groups(const Surface& s, std::span<const Index> fan, Index v) {
  const std::size_t k = fan.size();
  std::vector<Index> parent(k);
  std::iota(parent.begin(), parent.end(), Index(0));
  auto find = [&](Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j)
      for (Index u : s.triangles[fan[i]]) {
        if (u == v || !holds(s.triangles[fan[j]], u)) continue;
        if (std::binary_search(s.cut.begin(), s.cut.end(), edge(v, u))) continue;
        const Index a = find(Index(i)), b = find(Index(j));
        parent[std::max(a, b)] = std::min(a, b);  // the root is the group's lowest triangle
      }
  std::vector<Index> group(k), number(k, ~Index(0));
  Index groups = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const Index r = find(Index(i));
    if (number[r] == ~Index(0)) number[r] = groups++;
    group[i] = number[r];
  }
  return group;
}

// The groups a constraint on particles `ps` (one of them v) lies on: those of the fan's triangles whose corners
// are all among ps (for two particles: that hold both). Sorted, unique.
template <std::size_t N>
std::vector<Index> groups_of(const Surface& s, std::span<const Index> fan, const std::vector<Index>& group,
                             const std::array<Index, N>& ps) {
  std::vector<Index> out;
  if constexpr (N < 2) return out;  // on one particle (an anchor, a tether): stays with v
  for (std::size_t i = 0; i < fan.size(); ++i) {
    const auto& t = s.triangles[fan[i]];
    int in = 0;
    for (Index c : t) in += std::find(ps.begin(), ps.end(), c) != ps.end() ? 1 : 0;
    if (in >= int(std::min<std::size_t>(3, N))) out.push_back(group[i]);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Where each constraint touching a particle of `touched` is: (type, user index), per touched particle.
// One pass over every store, each particle looked up in a table of the touched ones.
template <class Real> struct Touching {
  std::vector<std::vector<std::pair<std::size_t, Index>>> at;
  Touching(const Model<Real>& m, const std::vector<Index>& touched) : at(touched.size()) {
    constexpr Index kNone = ~Index(0);
    std::vector<Index> slot(std::size_t(m.num_particles()), kNone);
    for (std::size_t i = 0; i < touched.size(); ++i) slot[touched[i]] = Index(i);
    for_each_store(m.stores, [&](const auto& st, auto t) {
      for (Index u = 0; u < Index(st.size()); ++u)
        for (Index p : st.at(u).particles)
          if (slot[p] != kNone) at[slot[p]].push_back({decltype(t)::value, u});
    });
  }
};

// Appends a copy of particle v with inverse mass w to s and m.
template <class Real> Index add_copy(Model<Real>& m, State<Real>& s, Index v, Real w) {
  const Index i = m.num_particles();
  m.inverse_mass.conservativeResize(i + 1);
  m.inverse_mass[i] = w;
  s.x.conservativeResize(3, i + 1);
  s.v.conservativeResize(3, i + 1);
  s.x.col(i) = s.x.col(v);
  s.v.col(i) = s.v.col(v);
  if (m.colors_current && m.fixed.size() == std::size_t(i)) m.fixed.push_back(w == Real(0));
  return i;
}

// Splits particle v of surface `sf` if its fan falls into several groups.
template <class Real>
void split(Model<Real>& m, State<Real>& s, Surface& sf, std::span<const Index> fan, Index v,
           const std::vector<std::pair<std::size_t, Index>>& touching, TearResult& out) {
  const std::vector<Index> group = fan_groups(sf, fan, v);
  const Index groups = group.empty() ? 0 : *std::max_element(group.begin(), group.end()) + 1;
  if (groups < 2) return;
  // v's mass split by triangle counts (a pinned particle's copies are pinned too)
  std::vector<Index> count(groups, 0);
  for (Index g : group) ++count[g];
  const Real w = m.inverse_mass[v];
  std::vector<Index> copy(groups, v);
  for (Index g = 1; g < groups; ++g) {
    copy[g] = add_copy(m, s, v, w * Real(fan.size()) / Real(count[g]));
    out.copies.push_back({copy[g], v});
  }
  m.inverse_mass[v] = w * Real(fan.size()) / Real(count[0]);
  for (std::size_t i = 0; i < fan.size(); ++i)
    for (Index& p : sf.triangles[fan[i]])
      if (p == v) p = copy[group[i]];
  for (const auto& touched : touching) {
    const auto type = touched.first;
    const auto u = touched.second;
    for_each_store(m.stores, [&](auto& st, auto t) {
      if (decltype(t)::value != type) return;
      auto& c = st.items[st.stored(u)];
      if (std::find(c.particles.begin(), c.particles.end(), v) == c.particles.end()) return;
      // the fan's triangles still name v in the groups that kept it: look it up by v's copies too
      std::array<Index, std::tuple_size_v<decltype(c.particles)>> ps = c.particles;
      const std::vector<Index> on = [&] {
        std::vector<Index> all;
        for (Index g = 0; g < groups; ++g) {
          for (Index& p : ps)
            if (p == v || std::find(copy.begin(), copy.end(), p) != copy.end()) p = copy[g];
          for (Index h : groups_of(sf, fan, group, ps))
            if (h == g) all.push_back(g);
        }
        return all;
      }();
      if (on.size() > 1) out.remove[type].push_back(u);
      else if (on.size() == 1 && on[0] != 0)
        for (Index& p : c.particles)
          if (p == v) p = copy[on[0]];
    });
  }
}

// Of the edges `wanted` (lower particle first, sorted), those that still have a fiber or a stretch constraint: one
// pass over the two stores, no sort of them, searching only for constraints between two particles of wanted edges.
template <class Real> std::vector<Edge> held_edges(const Model<Real>& m, const std::vector<Edge>& wanted) {
  std::vector<Edge> out;
  std::vector<std::uint8_t> on(std::size_t(m.num_particles()), 0);  // a particle of a wanted edge
  for (const Edge& e : wanted) on[e[0]] = on[e[1]] = 1;
  auto look = [&](Index a, Index b) {
    if (!on[a] || !on[b]) return;
    const Edge e = edge(a, b);
    if (std::binary_search(wanted.begin(), wanted.end(), e)) out.push_back(e);
  };
  for (const auto& c : m.template store<FiberConstraint<Real>>().items) look(c.particles[0], c.particles[1]);
  for (const auto& c : m.template store<StretchConstraint<Real>>().items) look(c.particles[0], c.particles[1]);
  std::sort(out.begin(), out.end());
  return out;
}

// Drops the triangles among `touched` (indices into sf.triangles) that have two or more edges with no fiber or
// stretch constraint left: a flap held by one edge at most, or a triangle left at a particle copy that no fiber
// holds. Each constraint of three or more particles lying on a dropped triangle (three of its particles are the
// triangle's: its area, a bending through it) is removed too.
template <class Real> void drop_flaps(const Model<Real>& m, Surface& sf, std::vector<Index> touched, TearResult& out) {
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  std::vector<Edge> wanted;
  for (Index k : touched)
    for (int i = 0; i < 3; ++i) wanted.push_back(edge(sf.triangles[k][i], sf.triangles[k][(i + 1) % 3]));
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  const std::vector<Edge> held = held_edges(m, wanted);
  auto is_held = [&](Index a, Index b) { return std::binary_search(held.begin(), held.end(), edge(a, b)); };
  std::vector<std::array<Index, 3>> dropped;
  std::vector<std::uint8_t> drop(sf.triangles.size(), 0);
  for (Index k : touched) {
    const auto& t = sf.triangles[k];
    const int open = int(!is_held(t[0], t[1])) + int(!is_held(t[1], t[2])) + int(!is_held(t[0], t[2]));
    if (open < 2) continue;
    drop[k] = 1;
    std::array<Index, 3> key = t;
    std::sort(key.begin(), key.end());
    dropped.push_back(key);
  }
  if (dropped.empty()) return;
  std::sort(dropped.begin(), dropped.end());
  for_each_store(m.stores, [&](const auto& st, auto type) {
    constexpr std::size_t n = std::tuple_size_v<decltype(st.items[0].particles)>;
    if constexpr (n >= 3) {
      for (Index u = 0; u < Index(st.size()); ++u) {
        const auto& ps = st.at(u).particles;
        bool on = false;
        for (std::size_t a = 0; a < n && !on; ++a)
          for (std::size_t b = a + 1; b < n && !on; ++b)
            for (std::size_t c = b + 1; c < n && !on; ++c) {
              std::array<Index, 3> key{ps[a], ps[b], ps[c]};
              std::sort(key.begin(), key.end());
              on = std::binary_search(dropped.begin(), dropped.end(), key);
            }
        if (on) out.remove[decltype(type)::value].push_back(u);
      }
    }
  });
  std::size_t kept = 0;
  for (std::size_t k = 0; k < sf.triangles.size(); ++k)
    if (!drop[k]) sf.triangles[kept++] = sf.triangles[k];
  sf.triangles.resize(kept);
}

}  // namespace

template <class Real> TearResult tear_surfaces(Model<Real>& m, State<Real>& s, std::span<const FiberBreak> breaks) {
  TearResult out;
  for (Surface& sf : m.surfaces) {
    const Incidence inc(sf, m.num_particles());
    std::vector<Index> ends;
    for (const FiberBreak& b : breaks) {
      if (b.arity != 2) continue;  // a surface tears along broken fibers, not tets
      const Index a = b.particles[0], c = b.particles[1];
      bool shared = false;  // an edge of the surface: a triangle holds both
      for (Index k : inc.of(a)) shared = shared || holds(sf.triangles[k], c);
      if (!shared) continue;
      const Edge e = edge(a, c);
      const auto at = std::lower_bound(sf.cut.begin(), sf.cut.end(), e);
      if (at == sf.cut.end() || *at != e) sf.cut.insert(at, e);
      ends.push_back(a);
      ends.push_back(c);
    }
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    if (ends.empty()) continue;
    const Touching<Real> touching(m, ends);
    std::vector<Index> fans;  // the triangles at the cut's ends: where flaps may be left
    for (std::size_t i = 0; i < ends.size(); ++i) {
      split(m, s, sf, inc.of(ends[i]), ends[i], touching.at[i], out);
      fans.insert(fans.end(), inc.of(ends[i]).begin(), inc.of(ends[i]).end());
    }
    drop_flaps(m, sf, fans, out);
  }
  for (auto& r : out.remove) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  return out;
}

template <class Real> void lay_out_after_tear(Model<Real>& m) {
  if (!m.colors_current) return;
  if (m.layout == Layout::blocks) {  // the copies are in no block: partitioned anew at the next step
    m.colors_current = false;
    return;
  }
  // A constraint moved to a copy keeps its color (no color had two constraints on v); in a tail color it must be
  // seen at the copy by the next first fit among the tail colors (constraint_store.hpp: color_tail).
  for_each_store(m.stores, [&](auto& st, auto) {
    if (st.tail_color == std::decay_t<decltype(st)>::kNoTail) return;
    st.tail_used.assign(m.fixed.size(), 0);
    for (Index c = st.tail_color; c < st.num_colors(); ++c)
      for (Index k = st.offsets[c]; k < st.offsets[c + 1]; ++k)
        for (Index p : st.items[k].particles)
          if (!m.fixed[p]) st.tail_used[p] |= std::uint64_t(1) << (c - st.tail_color);
  });
  note_layout(m);
}

template void lay_out_after_tear(Model<float>&);
template void lay_out_after_tear(Model<double>&);
template TearResult tear_surfaces(Model<float>&, State<float>&, std::span<const FiberBreak>);
template TearResult tear_surfaces(Model<double>&, State<double>&, std::span<const FiberBreak>);

}  // namespace pbd::detail
