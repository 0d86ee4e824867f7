// Coloring time per item for every algorithm (with and without balancing) on cloth stretch
// constraints and random hypergraphs of ~10^4, 10^5 and 10^6 items, with the coloring's figures as
// counters; plus, as the yardstick, one serial Gauss-Seidel sweep over the same cloth stretch
// constraints (float positions, PBD distance projection, natural order); plus partition() (both
// methods, 4, 16 and 64 parts) on 100 x 100 and 300 x 300 cloths' stretch and bending constraints.
//
// Counters: colors, lower_bound, max_over_mean (largest / mean regular batch), per_item (seconds
// per item; Google Benchmark prints it with an SI prefix, e.g. "4.1n" = 4.1 ns); for partitions,
// cut_fraction (cut items / items) and imbalance (largest / mean block weight, a node weighing the
// items touching it).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "inputs.hpp"
#include "pbd/graph_coloring/graph_coloring.hpp"

namespace {

using namespace pbd::coloring;

// Grid sizes whose triangulated cloth has ~10^4, 10^5, 10^6 unique edges.
std::uint32_t cloth_side(std::uint32_t items) { return items >= 1000000 ? 578 : items >= 100000 ? 183 : 58; }

const inputs::Graph& input(const std::string& kind, std::uint32_t items) {
  static std::map<std::pair<std::string, std::uint32_t>, inputs::Graph> cache;
  auto it = cache.find({kind, items});
  if (it == cache.end()) {
    inputs::Graph g = kind == "cloth" ? inputs::cloth_edges(cloth_side(items))
                                      : inputs::random_hypergraph(items, items / 2, 2, 4, 0, 12345);
    it = cache.emplace(std::make_pair(kind, items), std::move(g)).first;
  }
  return it->second;
}

void set_counters(benchmark::State& state, const Hypergraph& g, const Coloring& c) {
  const Stats s = compute_stats(g, c);
  state.counters["colors"] = s.num_colors;
  state.counters["lower_bound"] = s.lower_bound;
  state.counters["max_over_mean"] = s.max_over_mean;
  state.counters["per_item"] = benchmark::Counter(static_cast<double>(g.num_items()),
                                                  benchmark::Counter::kIsIterationInvariantRate |
                                                      benchmark::Counter::kInvert);
}

void bm_color(benchmark::State& state, std::string kind, Algorithm algorithm, bool balance) {
  const inputs::Graph& owned = input(kind, static_cast<std::uint32_t>(state.range(0)));
  const Hypergraph g = owned.view();
  Options options;
  options.algorithm = algorithm;
  options.balance = balance;
  Coloring c;
  for (auto _ : state) {
    c = color(g, options);
    benchmark::DoNotOptimize(c.color.data());
  }
  if (find_coloring_error(g, c)) state.SkipWithError("improper coloring");
  set_counters(state, g, c);
}

// Stretch (2 nodes: horizontal, vertical, one diagonal per cell) and bending (4 nodes: two triangles
// sharing an edge) constraints of an n x n cloth.
const inputs::Graph& cloth_with_bending(std::uint32_t n) {
  static std::map<std::uint32_t, inputs::Graph> cache;
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, inputs::merge(inputs::cloth_edges(n), inputs::cloth_bending(n))).first;
  return it->second;
}

// Arguments: cloth side, parts.
void bm_partition(benchmark::State& state, PartitionMethod method) {
  const inputs::Graph& owned = cloth_with_bending(static_cast<std::uint32_t>(state.range(0)));
  const Hypergraph g = owned.view();
  const PartitionOptions options{method, static_cast<std::uint32_t>(state.range(1))};
  Partition p;
  for (auto _ : state) {
    p = partition(g, options);
    benchmark::DoNotOptimize(p.block.data());
  }
  std::vector<std::uint64_t> block_weight(p.parts, 0);
  std::uint64_t total = 0;
  for (std::uint32_t v : owned.nodes)
    if (p.block[v] != kNoBlock) ++block_weight[p.block[v]], ++total;
  std::uint64_t largest = 0;
  for (auto w : block_weight) largest = std::max(largest, w);
  state.counters["parts"] = p.parts;
  state.counters["items"] = g.num_items();
  state.counters["cut_fraction"] = static_cast<double>(cut_items(g, p)) / g.num_items();
  state.counters["imbalance"] = p.parts == 0 ? 0.0 : static_cast<double>(largest) * p.parts / static_cast<double>(total);
}

// One Gauss-Seidel sweep of PBD distance constraints (k = 1) in natural (item) order.
void bm_sweep(benchmark::State& state) {
  const std::uint32_t n = cloth_side(static_cast<std::uint32_t>(state.range(0)));
  const inputs::Graph& owned = input("cloth", static_cast<std::uint32_t>(state.range(0)));
  const float spacing = 0.01f;
  std::vector<float> x(3 * static_cast<std::size_t>(owned.num_nodes));
  std::vector<float> w(owned.num_nodes, 1.0f);
  inputs::Rng rng{7};
  for (std::uint32_t v = 0; v < owned.num_nodes; ++v) {
    x[3 * v + 0] = static_cast<float>(v % n) * spacing + 0.002f * (static_cast<float>(rng.below(1000)) / 1000.0f - 0.5f);
    x[3 * v + 1] = static_cast<float>(v / n) * spacing + 0.002f * (static_cast<float>(rng.below(1000)) / 1000.0f - 0.5f);
    x[3 * v + 2] = 0.002f * (static_cast<float>(rng.below(1000)) / 1000.0f - 0.5f);
  }
  const std::uint32_t m = owned.num_items();
  std::vector<std::uint32_t> ends(owned.nodes);
  std::vector<float> rest(m);
  for (std::uint32_t i = 0; i < m; ++i) {
    const std::uint32_t a = ends[2 * i], b = ends[2 * i + 1];
    const float dx = static_cast<float>(a % n) - static_cast<float>(b % n);
    const float dy = static_cast<float>(a / n) - static_cast<float>(b / n);
    rest[i] = spacing * std::sqrt(dx * dx + dy * dy);
  }
  for (auto _ : state) {
    float* p = x.data();
    for (std::uint32_t i = 0; i < m; ++i) {
      const std::uint32_t a = ends[2 * i], b = ends[2 * i + 1];
      const float dx = p[3 * b] - p[3 * a], dy = p[3 * b + 1] - p[3 * a + 1], dz = p[3 * b + 2] - p[3 * a + 2];
      const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
      const float wsum = w[a] + w[b];
      if (len < 1e-9f || wsum == 0.0f) continue;
      const float s = (len - rest[i]) / (len * wsum);
      p[3 * a] += w[a] * s * dx, p[3 * a + 1] += w[a] * s * dy, p[3 * a + 2] += w[a] * s * dz;
      p[3 * b] -= w[b] * s * dx, p[3 * b + 1] -= w[b] * s * dy, p[3 * b + 2] -= w[b] * s * dz;
    }
    benchmark::DoNotOptimize(p);
    benchmark::ClobberMemory();
  }
  state.counters["per_item"] = benchmark::Counter(static_cast<double>(m), benchmark::Counter::kIsIterationInvariantRate |
                                                                              benchmark::Counter::kInvert);
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::int64_t> sizes{10000, 100000, 1000000};
  for (const std::string kind : {"cloth", "random"})
    for (Algorithm a : all_algorithms)
      for (bool balance : {false, true}) {
        const std::string label = std::string(balance ? "color+balance/" : "color/") + kind + "/" + std::string(name(a));
        auto* b = benchmark::RegisterBenchmark(label.c_str(), bm_color, kind, a, balance);
        for (auto s : sizes) b->Arg(s);
        b->Unit(benchmark::kMillisecond)->UseRealTime();
      }
  for (PartitionMethod method : {PartitionMethod::metis, PartitionMethod::index_ranges}) {
    const std::string label = std::string("partition/cloth+bending/") +
                              (method == PartitionMethod::metis ? "metis" : "index_ranges");
    auto* b = benchmark::RegisterBenchmark(label.c_str(), bm_partition, method);
    b->ArgNames({"side", "parts"})->ArgsProduct({{100, 300}, {4, 16, 64}});
    b->Unit(benchmark::kMillisecond)->UseRealTime();
  }
  auto* sweep = benchmark::RegisterBenchmark("reference/serial_gauss_seidel_sweep/cloth", bm_sweep);
  for (auto s : sizes) sweep->Arg(s);
  sweep->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
