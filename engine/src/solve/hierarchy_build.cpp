// Cooking the hierarchy (hierarchy.hpp's design note): level 0 from the stretch constraints, each coarser level by
// coarsening the one below, each level's constraints colored. Everything is in particle index order, so the same
// model gives the same hierarchy whatever order its stores are laid out in.
#include "hierarchy.hpp"

#include "schedule.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <pbd/graph_coloring/color.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace pbd::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr Index kNone = ~Index(0);

// A candidate constraint between two particles (world indices, a < b): a path of rest length `rest`.
struct Candidate {
  Index a, b;
  double rest, alpha;
  auto key() const { return std::tie(a, b, rest, alpha); }
};

// One level's particle graph, over level-local indices.
struct Graph {
  struct Edge {
    Index to;  // local
    double rest, alpha;
  };
  std::vector<Index> particles;  // world indices, ascending
  std::vector<Index> offsets;    // particle i's edges are [offsets[i], offsets[i + 1])
  std::vector<Edge> edges;       // each row by ascending `to`
  std::vector<double> mass;      // per particle, kg (infinite: pinned)
  std::vector<Candidate> pairs;  // its edges once each (a < b), ascending: the level's constraints
};

// The graph of `particles` (world indices, ascending) joined by `candidates` (deduplicated here: the shortest path
// of a pair counts, then the least compliant). `local` maps world to local indices (kNone elsewhere, left so).
Graph make_graph(std::vector<Index> particles, std::vector<Candidate> candidates, std::vector<Index>& local) {
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) { return x.key() < y.key(); });
  Graph g;
  for (const Candidate& c : candidates)
    if (g.pairs.empty() || g.pairs.back().a != c.a || g.pairs.back().b != c.b) g.pairs.push_back(c);
  g.particles = std::move(particles);
  for (std::size_t i = 0; i < g.particles.size(); ++i) local[g.particles[i]] = Index(i);
  std::vector<Index> degree(g.particles.size() + 1, 0);
  for (const Candidate& c : g.pairs) {
    ++degree[local[c.a] + 1];
    ++degree[local[c.b] + 1];
  }
  for (std::size_t i = 1; i < degree.size(); ++i) degree[i] += degree[i - 1];
  g.offsets = degree;
  g.edges.resize(g.offsets.back());
  for (const Candidate& c : g.pairs) {
    const Index la = local[c.a], lb = local[c.b];
    g.edges[degree[la]++] = {lb, c.rest, c.alpha};
    g.edges[degree[lb]++] = {la, c.rest, c.alpha};
  }
  for (std::size_t i = 0; i + 1 < g.offsets.size(); ++i)
    std::sort(g.edges.begin() + g.offsets[i], g.edges.begin() + g.offsets[i + 1],
              [](const Graph::Edge& x, const Graph::Edge& y) { return x.to < y.to; });
  for (Index p : g.particles) local[p] = kNone;
  return g;
}

// Level 0: the stretch constraints' particles and edges, with the world's masses.
template <class Real> Graph fine_graph(const Model<Real>& m, bool compliant, std::vector<Index>& local) {
  const auto& items = m.template store<StretchConstraint<Real>>().items;
  std::vector<Candidate> candidates;
  candidates.reserve(items.size());
  std::vector<std::uint8_t> used(std::size_t(m.num_particles()), 0);
  for (const auto& c : items) {
    const Stiffness& s = m.sets[c.set];
    const double alpha = s.mode == StiffnessMode::xpbd ? s.compliance : 0.0;
    if (alpha > 0 && !compliant) continue;
    const Index a = std::min(c.particles[0], c.particles[1]), b = std::max(c.particles[0], c.particles[1]);
    candidates.push_back({a, b, double(c.rest), alpha});
    used[a] = used[b] = 1;
  }
  std::vector<Index> particles;
  for (std::size_t i = 0; i < used.size(); ++i)
    if (used[i]) particles.push_back(Index(i));
  Graph g = make_graph(std::move(particles), std::move(candidates), local);
  g.mass.resize(g.particles.size());
  for (std::size_t i = 0; i < g.particles.size(); ++i) {
    const Real w = m.inverse_mass[g.particles[i]];
    g.mass[i] = w == Real(0) ? kInf : 1.0 / double(w);
  }
  return g;
}

// Which of g's particles the next level keeps (the design note's steps 1–3), in index order.
std::vector<std::uint8_t> choose_coarse(const Graph& g, int k) {
  enum : std::uint8_t { undecided, coarse, fine };
  const std::size_t n = g.particles.size();
  std::vector<std::uint8_t> state(n, undecided);
  auto keep = [&](std::size_t i) {
    state[i] = coarse;
    for (Index e = g.offsets[i]; e < g.offsets[i + 1]; ++e)
      if (state[g.edges[e].to] == undecided) state[g.edges[e].to] = fine;
  };
  for (std::size_t i = 0; i < n; ++i)
    if (std::isinf(g.mass[i])) state[i] = coarse;  // pinned particles stay pinned in every level
  for (std::size_t i = 0; i < n; ++i)
    if (state[i] == coarse) keep(i);
  for (std::size_t i = 0; i < n; ++i)
    if (state[i] == undecided) keep(i);
  for (std::size_t i = 0; i < n; ++i) {
    if (state[i] != fine) continue;
    int parents = 0;
    for (Index e = g.offsets[i]; e < g.offsets[i + 1]; ++e) parents += state[g.edges[e].to] == coarse;
    if (parents < k) state[i] = coarse;
  }
  for (auto& s : state) s = s == coarse;
  return state;
}

// The next level's graph from g and its choice: coarse particles joined directly or through one particle left out.
Graph coarse_graph(const Graph& g, const std::vector<std::uint8_t>& coarse, std::vector<Index>& local) {
  std::vector<Candidate> candidates;
  std::vector<Index> particles;
  for (std::size_t a = 0; a < g.particles.size(); ++a) {
    if (!coarse[a]) continue;
    particles.push_back(g.particles[a]);
    for (Index e = g.offsets[a]; e < g.offsets[a + 1]; ++e) {
      const Graph::Edge& ax = g.edges[e];
      if (coarse[ax.to]) {
        if (ax.to > a) candidates.push_back({g.particles[a], g.particles[ax.to], ax.rest, ax.alpha});
        continue;
      }
      for (Index f = g.offsets[ax.to]; f < g.offsets[ax.to + 1]; ++f) {
        const Graph::Edge& xy = g.edges[f];
        if (coarse[xy.to] && xy.to > a)
          candidates.push_back({g.particles[a], g.particles[xy.to], ax.rest + xy.rest, ax.alpha + xy.alpha});
      }
    }
  }
  return make_graph(std::move(particles), std::move(candidates), local);
}

// The interpolation of g's particles left out (weights ∝ 1 / rest length), and the coarse masses it implies
// (each coarse particle gains w·m of each particle naming it with weight w).
template <class Real> void interpolate(const Graph& g, const std::vector<std::uint8_t>& coarse, Graph& next,
                                       HierarchyLevel<Real>& level) {
  next.mass.assign(next.particles.size(), 0.0);
  std::size_t j = 0;
  for (std::size_t i = 0; i < g.particles.size(); ++i)
    if (coarse[i]) next.mass[j++] = g.mass[i];
  level.parent_offsets.assign(1, 0);
  for (std::size_t i = 0; i < g.particles.size(); ++i) {
    if (coarse[i]) continue;
    const std::size_t first = level.parents.size();
    double sum = 0;
    for (Index e = g.offsets[i]; e < g.offsets[i + 1]; ++e) {
      if (!coarse[g.edges[e].to]) continue;
      const double w = 1.0 / std::max(g.edges[e].rest, 1e-9);
      level.parents.push_back(g.particles[g.edges[e].to]);
      level.weights.push_back(Real(w));
      sum += w;
    }
    for (std::size_t q = first; q < level.parents.size(); ++q) {
      const double w = double(level.weights[q]) / sum;
      level.weights[q] = Real(w);
      const auto at = std::lower_bound(next.particles.begin(), next.particles.end(), level.parents[q]);
      next.mass[std::size_t(at - next.particles.begin())] += w * g.mass[i];
    }
    level.fine.push_back(g.particles[i]);
    level.parent_offsets.push_back(Index(level.parents.size()));
  }
}

// The level's constraints, colored (graph_coloring) and stored color by color, each with its path's rest length
// stretched by the slack.
template <class Real> void store_constraints(const Model<Real>& m, const Graph& g, const std::vector<std::uint8_t>& fixed,
                                             double slack, HierarchyLevel<Real>& level) {
  std::vector<std::uint32_t> offsets{0}, nodes;
  for (const Candidate& c : g.pairs) {
    nodes.push_back(std::uint32_t(c.a));
    nodes.push_back(std::uint32_t(c.b));
    offsets.push_back(std::uint32_t(nodes.size()));
  }
  const coloring::Hypergraph graph{offsets, nodes, std::uint32_t(m.num_particles()), fixed};
  coloring::Coloring col;
  try {
    col = coloring::color(graph, m.coloring);
  } catch (const coloring::Error& e) {
    throw Error(std::string("coloring the hierarchy's constraints: ") + e.what());
  }
  auto inverse = [&](Index p) {
    const std::size_t i = std::size_t(std::lower_bound(g.particles.begin(), g.particles.end(), p) - g.particles.begin());
    return std::isinf(g.mass[i]) ? Real(0) : Real(1.0 / g.mass[i]);
  };
  level.particles = g.particles;
  level.color_offsets.assign(col.color_offsets.begin(), col.color_offsets.end());
  for (std::uint32_t item : col.items) {
    const Candidate& c = g.pairs[item];
    level.pairs.push_back({c.a, c.b});
    level.w.push_back({inverse(c.a), inverse(c.b)});
    level.rest.push_back(Real(c.rest * (1.0 + slack)));
    level.compliance.push_back(Real(c.alpha));
  }
}

}  // namespace

template <class Real> HierarchyModel<Real> build_hierarchy(const Model<Real>& m, const Hierarchy& settings) {
  HierarchyModel<Real> h;
  h.edits = m.edits;
  h.num_sets = m.sets.size();
  h.settings = settings;
  std::vector<Index> local(std::size_t(m.num_particles()), kNone);
  const std::vector<std::uint8_t> fixed = pinned_flags(m.inverse_mass);
  Graph g = fine_graph(m, settings.compliant, local);
  h.fine_particles = Index(g.particles.size());
  for (int l = 0; l < settings.levels && !g.pairs.empty(); ++l) {
    const std::vector<std::uint8_t> coarse = choose_coarse(g, settings.parents);
    const std::size_t kept = std::size_t(std::count(coarse.begin(), coarse.end(), std::uint8_t(1)));
    if (double(kept) > 0.9 * double(g.particles.size())) break;
    Graph next = coarse_graph(g, coarse, local);
    HierarchyLevel<Real> level;
    interpolate(g, coarse, next, level);
    store_constraints(m, next, fixed, settings.slack, level);
    h.levels.push_back(std::move(level));
    g = std::move(next);
  }
  return h;
}

template <class Real> void ensure_hierarchy(Model<Real>& m, const Hierarchy& settings) {
  const HierarchyModel<Real>* h = m.hierarchy.get();
  if (h && h->edits == m.edits && h->num_sets == m.sets.size() && h->settings == settings) return;
  m.hierarchy = std::make_shared<const HierarchyModel<Real>>(build_hierarchy(m, settings));
}

template HierarchyModel<float> build_hierarchy(const Model<float>&, const Hierarchy&);
template HierarchyModel<double> build_hierarchy(const Model<double>&, const Hierarchy&);
template void ensure_hierarchy(Model<float>&, const Hierarchy&);
template void ensure_hierarchy(Model<double>&, const Hierarchy&);

}  // namespace pbd::detail
