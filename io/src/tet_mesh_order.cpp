#include "pbd/io/tet_mesh.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

namespace pbd {
namespace {

constexpr Index kLeaf = 32;  // a part this small keeps its order: it fits in a few cache lines anyway

// The vertices in recursive coordinate bisection order (tet_mesh.hpp): order[k] is the k-th vertex.
std::vector<Index> bisection_order(const Matrix3X<double>& x) {
  const Index n = Index(x.cols());
  std::vector<Index> order(n);
  std::iota(order.begin(), order.end(), Index(0));
  std::vector<std::pair<Index, Index>> parts{{0, n}};
  while (!parts.empty()) {
    const auto [b, e] = parts.back();
    parts.pop_back();
    if (e - b <= kLeaf) {
      std::sort(order.begin() + b, order.begin() + e);
      continue;
    }
    Vec3<double> lo = x.col(order[b]), hi = lo;
    for (Index k = b + 1; k < e; ++k) {
      lo = lo.cwiseMin(x.col(order[k]));
      hi = hi.cwiseMax(x.col(order[k]));
    }
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    const Index mid = b + (e - b) / 2;
    std::nth_element(order.begin() + b, order.begin() + mid, order.begin() + e, [&](Index i, Index j) {
      return x(axis, i) < x(axis, j) || (x(axis, i) == x(axis, j) && i < j);
    });
    parts.emplace_back(mid, e);
    parts.emplace_back(b, mid);
  }
  return order;
}

}  // namespace

TetMesh spatially_ordered(const TetMesh& mesh, std::vector<Index>* new_index) {
  check_tet_mesh(mesh, "spatially_ordered");  // every tet's vertices in range
  const std::vector<Index> order = bisection_order(mesh.positions);
  std::vector<Index> at(order.size());
  TetMesh out;
  out.positions.resize(3, mesh.positions.cols());
  for (Index k = 0; k < Index(order.size()); ++k) {
    at[order[k]] = k;
    out.positions.col(k) = mesh.positions.col(order[k]);
  }
  out.tets = mesh.tets;
  for (auto& t : out.tets)
    for (Index& v : t) v = at[v];
  auto smallest = [](const std::array<Index, 4>& t) { return *std::min_element(t.begin(), t.end()); };
  std::stable_sort(out.tets.begin(), out.tets.end(), [&](const auto& a, const auto& b) { return smallest(a) < smallest(b); });
  if (new_index) *new_index = std::move(at);
  return out;
}

}  // namespace pbd
