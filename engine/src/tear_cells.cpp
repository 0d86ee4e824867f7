// Tearing volumes along broken fibers (tear_cells.hpp).
#include "tear_cells.hpp"

#include <algorithm>
#include <cstdint>

namespace pbd::detail {

template <class Real>
std::array<std::vector<Index>, kNumBuiltinTypes> cells_on_broken_fibers(const Model<Real>& m,
                                                                        std::span<const FiberBreak> breaks) {
  std::array<std::vector<Index>, kNumBuiltinTypes> out;
  using Edge = std::array<Index, 2>;
  using Cell = std::array<Index, 4>;
  std::vector<Edge> edges;  // broken fibers' ends, each pair sorted
  std::vector<Cell> cells;  // broken tet fibers' corners, sorted
  std::vector<std::uint8_t> end(std::size_t(m.num_particles()), 0);  // a particle of a broken constraint
  for (const FiberBreak& b : breaks) {
    for (int i = 0; i < b.arity; ++i) end[b.particles[std::size_t(i)]] = 1;
    if (b.arity == 2) edges.push_back({std::min(b.particles[0], b.particles[1]), std::max(b.particles[0], b.particles[1])});
    if (b.arity == 4) {
      Cell c = b.particles;
      std::sort(c.begin(), c.end());
      cells.push_back(c);
    }
  }
  std::sort(edges.begin(), edges.end());
  std::sort(cells.begin(), cells.end());
  for_each_store(m.stores, [&](const auto& st, auto type) {
    using C = typename std::decay_t<decltype(st)>::value_type;
    if constexpr (breaks_with_fibers<C>()) {
      for (Index u = 0; u < Index(st.size()); ++u) {
        const auto& ps = st.at(u).particles;
        bool torn = false;
        for (std::size_t i = 0; i < ps.size() && !torn; ++i)
          for (std::size_t j = i + 1; j < ps.size() && !torn; ++j)
            torn = end[ps[i]] && end[ps[j]] &&
                   std::binary_search(edges.begin(), edges.end(), Edge{std::min(ps[i], ps[j]), std::max(ps[i], ps[j])});
        if constexpr (std::tuple_size_v<std::decay_t<decltype(ps)>> == 4) {
          if (!torn && !cells.empty()) {
            Cell c = ps;
            std::sort(c.begin(), c.end());
            torn = std::binary_search(cells.begin(), cells.end(), c);
          }
        }
        if (torn) out[decltype(type)::value].push_back(u);
      }
    }
  });
  return out;
}

template std::array<std::vector<Index>, kNumBuiltinTypes> cells_on_broken_fibers(const Model<float>&,
                                                                                 std::span<const FiberBreak>);
template std::array<std::vector<Index>, kNumBuiltinTypes> cells_on_broken_fibers(const Model<double>&,
                                                                                 std::span<const FiberBreak>);

}  // namespace pbd::detail
