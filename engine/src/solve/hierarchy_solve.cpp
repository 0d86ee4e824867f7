// The hierarchy's coarse-to-fine pass and its invariants (hierarchy.hpp's design note).
#include "hierarchy.hpp"

#include "pbd/detail/message.hpp"

#include <algorithm>
#include <cmath>

namespace pbd::detail {

template <class Real>
void project_level(const HierarchyLevel<Real>& level, Real inv_h2, Real* p, Real* lambda, Index b, Index e) {
  for (Index c = b; c < e; ++c) {
    const auto [i, j] = level.pairs[c];
    Real* pi = p + 3 * std::size_t(i);
    Real* pj = p + 3 * std::size_t(j);
    const Real d[3] = {pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]};
    const Real len2 = d[0] * d[0] + (d[1] * d[1] + d[2] * d[2]);
    if (!(len2 > tiny_squared<Real>())) continue;
    const Real len = std::sqrt(len2);
    const Real alpha_tilde = level.compliance[c] * inv_h2;
    const Real wi = level.w[c][0], wj = level.w[c][1];
    const Real denom = wi + wj + alpha_tilde;
    if (!(denom > Real(0))) continue;
    const Real dlambda = std::min(-lambda[c], (-(len - level.rest[c]) - alpha_tilde * lambda[c]) / denom);
    if (dlambda == Real(0) || dlambda != dlambda) continue;  // one-sided: λ stays ≤ 0, so a slack pair is let go
    lambda[c] += dlambda;
    const Real s = dlambda / len;
    if (wi != Real(0))
      for (int k = 0; k < 3; ++k) pi[k] += wi * s * d[k];
    if (wj != Real(0))
      for (int k = 0; k < 3; ++k) pj[k] -= wj * s * d[k];
  }
}

template <class Real>
void interpolate_level(const HierarchyLevel<Real>& level, const Real* start, Real* p, Index b, Index e) {
  for (Index f = b; f < e; ++f) {
    Real delta[3] = {0, 0, 0};
    for (Index q = level.parent_offsets[f]; q < level.parent_offsets[f + 1]; ++q) {
      const std::size_t j = 3 * std::size_t(level.parents[q]);
      const Real w = level.weights[q];
      for (int k = 0; k < 3; ++k) delta[k] += w * (p[j + k] - start[j + k]);
    }
    const std::size_t i = 3 * std::size_t(level.fine[f]);
    for (int k = 0; k < 3; ++k) p[i + k] += delta[k];
  }
}

template <class Real> void prepare_hierarchy(const HierarchyModel<Real>& hm, HierarchyScratch<Real>& k, Index n) {
  k.start.resize(3 * std::size_t(n));
  k.lambda_offsets.assign(hm.levels.size() + 1, 0);
  for (std::size_t l = 0; l < hm.levels.size(); ++l)
    k.lambda_offsets[l + 1] = k.lambda_offsets[l] + hm.levels[l].pairs.size();
  k.lambda.resize(k.lambda_offsets.back());
}

template <class Real>
std::string validate_hierarchy(const HierarchyModel<Real>& h, const Model<Real>& m, const Matrix3X<Real>* x) {
  const std::size_t n = std::size_t(m.num_particles());
  std::vector<std::uint8_t> in_finer(n, 0), in_level(n, 0);
  for (const auto& c : m.template store<StretchConstraint<Real>>().items) {
    const Stiffness& s = m.sets[c.set];
    if (h.settings.compliant || s.mode != StiffnessMode::xpbd || !(s.compliance > 0))
      in_finer[c.particles[0]] = in_finer[c.particles[1]] = 1;
  }
  for (std::size_t l = 0; l < h.levels.size(); ++l) {
    const HierarchyLevel<Real>& level = h.levels[l];
    auto where = [&](auto... what) { return message("hierarchy level ", l + 1, ": ", what...); };
    std::fill(in_level.begin(), in_level.end(), std::uint8_t(0));
    for (Index p : level.particles) {
      if (!in_finer[p]) return where("particle ", p, " is not in the finer level");
      in_level[p] = 1;
    }
    for (std::size_t i = 0; i < n; ++i)
      if (in_finer[i] && m.inverse_mass[Index(i)] == Real(0) && !in_level[i]) return where("pinned particle ", i, " left out");
    std::size_t fine = 0;
    for (std::size_t i = 0; i < n; ++i) fine += in_finer[i] && !in_level[i];
    if (fine != level.fine.size()) return where(level.fine.size(), " particles interpolated, ", fine, " left out");
    for (std::size_t f = 0; f < level.fine.size(); ++f) {
      const Index count = level.parent_offsets[f + 1] - level.parent_offsets[f];
      if (in_level[level.fine[f]]) return where("interpolated particle ", level.fine[f], " is in the level");
      if (count < Index(h.settings.parents)) return where("particle ", level.fine[f], " has ", count, " parents");
      double sum = 0;
      for (Index q = level.parent_offsets[f]; q < level.parent_offsets[f + 1]; ++q) {
        if (!in_level[level.parents[q]]) return where("parent ", level.parents[q], " is not in the level");
        if (!(level.weights[q] > Real(0))) return where("particle ", level.fine[f], " has a weight <= 0");
        sum += double(level.weights[q]);
      }
      if (std::abs(sum - 1.0) > 1e-5) return where("particle ", level.fine[f], "'s weights sum to ", sum);
    }
    for (std::size_t c = 0; c + 1 < level.color_offsets.size(); ++c) {
      std::vector<std::uint8_t> written(n, 0);
      for (Index q = level.color_offsets[c]; q < level.color_offsets[c + 1]; ++q)
        for (int s = 0; s < 2; ++s) {
          const Index p = level.pairs[q][s];
          if (!in_level[p]) return where("constraint ", q, " names particle ", p, " outside the level");
          if ((m.inverse_mass[p] == Real(0)) != (level.w[q][s] == Real(0))) return where("constraint ", q, ": pinned flag");
          if (level.w[q][s] != Real(0) && written[p]++) return where("color ", c, " writes particle ", p, " twice");
        }
    }
    for (std::size_t q = 0; q < level.pairs.size(); ++q) {
      if (!(level.rest[q] >= Real(0)) || !(level.compliance[q] >= Real(0))) return where("constraint ", q, ": rest or compliance");
      if (x) {
        const Real d = (x->col(level.pairs[q][0]) - x->col(level.pairs[q][1])).norm();
        if (level.rest[q] < d * (Real(1) - Real(1e-5))) return where("constraint ", q, ": rest ", level.rest[q], " < distance ", d);
      }
    }
    in_finer = in_level;
  }
  return {};
}

#define PBD_HIERARCHY_PASS_INSTANTIATE(Real)                                                                    \
  template void project_level(const HierarchyLevel<Real>&, Real, Real*, Real*, Index, Index);                     \
  template void interpolate_level(const HierarchyLevel<Real>&, const Real*, Real*, Index, Index);                 \
  template void prepare_hierarchy(const HierarchyModel<Real>&, HierarchyScratch<Real>&, Index);
PBD_HIERARCHY_PASS_INSTANTIATE(float)
PBD_HIERARCHY_PASS_INSTANTIATE(double)
#undef PBD_HIERARCHY_PASS_INSTANTIATE
template std::string validate_hierarchy(const HierarchyModel<float>&, const Model<float>&, const Matrix3X<float>*);
template std::string validate_hierarchy(const HierarchyModel<double>&, const Model<double>&, const Matrix3X<double>*);

}  // namespace pbd::detail
