// Generating a body's tethers (pbd/tethers.hpp): find its sources, measure each movable particle's length to them
// (straight, or Dijkstra along the stretch constraints), and keep the nearest or all.
#include "pbd/tethers.hpp"

#include "pbd/checks.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <cmath>
#include <limits>
#include <queue>
#include <tuple>

namespace pbd {

std::optional<TetherTo> parse_tether_to(std::string_view name) {
  if (name == "nearest") return TetherTo::nearest;
  if (name == "all") return TetherTo::all;
  return std::nullopt;
}

std::optional<TetherLength> parse_tether_length(std::string_view name) {
  if (name == "euclidean") return TetherLength::euclidean;
  if (name == "geodesic") return TetherLength::geodesic;
  return std::nullopt;
}

void check_tether_request(std::span<const Index> body, std::size_t n, const TetherOptions& options, const char* fn) {
  std::vector<bool> seen(n, false);
  for (std::size_t k = 0; k < body.size(); ++k) {
    const Index i = body[k];
    if (i >= n)
      throw Error(detail::message(fn, ": particle index ", i, " out of range (the world has ", n, " particles)"));
    if (seen[i]) throw Error(detail::message(fn, ": particle ", i, " is listed twice"));
    seen[i] = true;
  }
  if (!std::isfinite(options.compliance) || options.compliance < 0.0)
    throw Error(detail::message(fn, ": compliance must be finite and >= 0, got ", options.compliance));
}

namespace {

constexpr double kUnreached = std::numeric_limits<double>::infinity();
constexpr Index kNone = std::numeric_limits<Index>::max();

// A particle a tether can hang from: the particle, its target and the target's distance from it.
struct Source {
  Index particle;
  Eigen::Vector3d target;
  double offset;
};

template <class Real> Eigen::Vector3d at(const TetherInputs<Real>& in, Index i) {
  return in.positions->col(i).template cast<double>();
}

// The body's pinned particles and anchored ones (first anchor in insertion order), in body order.
template <class Real> std::vector<Source> find_sources(const TetherInputs<Real>& in, std::vector<Index>& local) {
  std::vector<Index> anchor_of(in.body.size(), kNone);
  for (std::size_t a = 0; a < in.anchors.size(); ++a) {
    const Index l = local[in.anchors[a].particles[0]];
    if (l != kNone && anchor_of[l] == kNone) anchor_of[l] = Index(a);
  }
  std::vector<Source> sources;
  for (std::size_t l = 0; l < in.body.size(); ++l) {
    const Index i = in.body[l];
    if ((*in.inverse_masses)[i] == Real(0)) {
      sources.push_back({i, at(in, i), 0.0});
    } else if (anchor_of[l] != kNone) {
      const Eigen::Vector3d t = in.anchors[anchor_of[l]].target.template cast<double>();
      sources.push_back({i, t, (at(in, i) - t).norm()});
    }
  }
  return sources;
}

// Shortest rest-length paths over the body's stretch constraints from the sources [first, last): per local particle
// the length and the source it comes from (lexicographic (length, source) keys, so ties go to the first source).
struct Graph {
  std::vector<Index> start, next;  // CSR: neighbours of local l are next[start[l], start[l + 1])
  std::vector<double> weight;
};

template <class Real> Graph stretch_graph(const TetherInputs<Real>& in, const std::vector<Index>& local) {
  Graph g;
  const std::size_t n = in.body.size();
  g.start.assign(n + 1, 0);
  auto both = [&](const StretchConstraint<Real>& s) {
    return local[s.particles[0]] != kNone && local[s.particles[1]] != kNone;
  };
  for (const auto& s : in.stretch)
    if (both(s)) ++g.start[local[s.particles[0]] + 1], ++g.start[local[s.particles[1]] + 1];
  for (std::size_t l = 0; l < n; ++l) g.start[l + 1] += g.start[l];
  g.next.resize(g.start[n]);
  g.weight.resize(g.start[n]);
  std::vector<Index> fill(g.start.begin(), g.start.end() - 1);
  for (const auto& s : in.stretch) {
    if (!both(s)) continue;
    const Index a = local[s.particles[0]], b = local[s.particles[1]];
    g.next[fill[a]] = b, g.weight[fill[a]++] = double(s.rest);
    g.next[fill[b]] = a, g.weight[fill[b]++] = double(s.rest);
  }
  return g;
}

void dijkstra(const Graph& g, const std::vector<Source>& sources, const std::vector<Index>& local, std::size_t first,
              std::size_t last, std::vector<double>& dist, std::vector<Index>& from) {
  using Key = std::tuple<double, Index, Index>;  // length, source, local particle
  std::priority_queue<Key, std::vector<Key>, std::greater<>> queue;
  dist.assign(g.start.size() - 1, kUnreached);
  from.assign(g.start.size() - 1, kNone);
  for (std::size_t s = first; s < last; ++s) {
    const Index l = local[sources[s].particle];
    if (std::tie(sources[s].offset, s) < std::tie(dist[l], from[l])) {
      dist[l] = sources[s].offset;
      from[l] = Index(s);
      queue.emplace(dist[l], Index(s), l);
    }
  }
  while (!queue.empty()) {
    const auto [d, s, l] = queue.top();
    queue.pop();
    if (d != dist[l] || s != from[l]) continue;  // a stale entry
    for (Index e = g.start[l]; e < g.start[l + 1]; ++e) {
      const Index m = g.next[e];
      const double dm = d + g.weight[e];
      if (std::tie(dm, s) < std::tie(dist[m], from[m])) {
        dist[m] = dm;
        from[m] = s;
        queue.emplace(dm, s, m);
      }
    }
  }
}

}  // namespace

template <class Real>
std::vector<TetherConstraint<Real>> plan_tethers(const TetherInputs<Real>& in, const TetherOptions& options, Index set) {
  const std::size_t n = std::size_t(in.positions->cols());
  std::vector<Index> local(n, kNone);
  for (std::size_t l = 0; l < in.body.size(); ++l) local[in.body[l]] = Index(l);
  const std::vector<Source> sources = find_sources(in, local);
  std::vector<TetherConstraint<Real>> out;
  if (sources.empty()) return out;
  std::vector<bool> is_source(in.body.size(), false);
  for (const Source& s : sources) is_source[local[s.particle]] = true;
  // lengths[k][l]: the length from source k (every source for "all"; the nearest, slot 0, for "nearest").
  const std::size_t passes = options.to == TetherTo::all ? sources.size() : 1;
  std::vector<std::vector<double>> lengths(passes);
  std::vector<std::vector<Index>> from(passes);
  if (options.length == TetherLength::geodesic) {
    const Graph g = stretch_graph(in, local);
    for (std::size_t k = 0; k < passes; ++k)
      dijkstra(g, sources, local, passes == 1 ? 0 : k, passes == 1 ? sources.size() : k + 1, lengths[k], from[k]);
  } else {
    for (std::size_t k = 0; k < passes; ++k) {
      lengths[k].assign(in.body.size(), kUnreached);
      from[k].assign(in.body.size(), kNone);
      for (std::size_t l = 0; l < in.body.size(); ++l)
        for (std::size_t s = passes == 1 ? 0 : k; s < (passes == 1 ? sources.size() : k + 1); ++s) {
          const double d = (at(in, in.body[l]) - sources[s].target).norm();
          if (d < lengths[k][l]) lengths[k][l] = d, from[k][l] = Index(s);
        }
    }
  }
  for (std::size_t l = 0; l < in.body.size(); ++l) {
    const Index i = in.body[l];
    if (is_source[l] || (*in.inverse_masses)[i] == Real(0)) continue;
    for (std::size_t k = 0; k < passes; ++k) {
      if (from[k][l] == kNone) continue;  // no path along the stretch constraints
      const Source& s = sources[from[k][l]];
      Real length = Real(lengths[k][l]);
      if (double(length) < lengths[k][l]) length = std::nextafter(length, std::numeric_limits<Real>::infinity());
      // rounded up: a particle at its rest length is not pulled by a rounding
      TetherConstraint<Real> t{{i}, set, s.target.cast<Real>(), length, s.particle};
      out.push_back(t);
    }
  }
  return out;
}

template std::vector<TetherConstraint<float>> plan_tethers(const TetherInputs<float>&, const TetherOptions&, Index);
template std::vector<TetherConstraint<double>> plan_tethers(const TetherInputs<double>&, const TetherOptions&, Index);

}  // namespace pbd
