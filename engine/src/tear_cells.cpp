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
  std::vector<Edge> broken;
  std::vector<std::uint8_t> end(std::size_t(m.num_particles()), 0);  // an end of a broken fiber
  for (const FiberBreak& b : breaks) {
    broken.push_back({std::min(b.a, b.b), std::max(b.a, b.b)});
    end[b.a] = end[b.b] = 1;
  }
  std::sort(broken.begin(), broken.end());
  for_each_store(m.stores, [&](const auto& st, auto type) {
    using C = typename std::decay_t<decltype(st)>::value_type;
    if constexpr (breaks_with_fibers<C>()) {
      for (Index u = 0; u < Index(st.size()); ++u) {
        const auto& ps = st.at(u).particles;
        bool torn = false;
        for (std::size_t i = 0; i < ps.size() && !torn; ++i)
          for (std::size_t j = i + 1; j < ps.size() && !torn; ++j)
            torn = end[ps[i]] && end[ps[j]] &&
                   std::binary_search(broken.begin(), broken.end(),
                                      Edge{std::min(ps[i], ps[j]), std::max(ps[i], ps[j])});
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
