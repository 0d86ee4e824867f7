// The hierarchy's coarse-to-fine pass and its invariants (hierarchy.hpp's design note).
#include "hierarchy.hpp"

#include "parallel_range.hpp"
#include "pbd/detail/message.hpp"

#include <algorithm>
#include <cmath>

namespace pbd::detail {
namespace {

// One-sided XPBD projection of coarse constraints [b, e) of `level` on p (3 per particle): only a pair longer than
// its rest length is pulled together, and its accumulated λ never pushes (λ ≤ 0).
template <class Real>
void project(const HierarchyLevel<Real>& level, Real inv_h2, Real* p, Real* lambda, Index b, Index e) {
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

// Particles [b, e) of level.fine move by their parents' corrections since the pass began.
template <class Real> void interpolate(const HierarchyLevel<Real>& level, const Real* start, Real* p, Index b, Index e) {
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

}  // namespace

template <class Real>
void run_hierarchy(const HierarchyModel<Real>& hm, HierarchyScratch<Real>& k, Matrix3X<Real>& positions, Real h,
                   bool parallel, const ParallelConfig& config) {
  if (hm.levels.empty()) return;
  Real* p = positions.data();
  const std::size_t n = std::size_t(positions.size());
  k.start.assign(p, p + n);
  const Real inv_h2 = Real(1) / (h * h);
  std::size_t loop = 0;
  for (std::size_t l = hm.levels.size(); l-- > 0;) {
    const HierarchyLevel<Real>& level = hm.levels[l];
    k.lambda.assign(level.pairs.size(), Real(0));
    Real* lambda = k.lambda.data();
    for (int sweep = 0; sweep < hm.settings.sweeps; ++sweep)
      for (std::size_t c = 0; c + 1 < level.color_offsets.size(); ++c)
        run_range(level.color_offsets[c], level.color_offsets[c + 1], parallel, config, k.partitioners[loop++],
                  [&](Index b, Index e) { project(level, inv_h2, p, lambda, b, e); });
    run_range(0, Index(level.fine.size()), parallel, config, k.partitioners[loop++],
              [&](Index b, Index e) { interpolate(level, k.start.data(), p, b, e); });
  }
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

template void run_hierarchy(const HierarchyModel<float>&, HierarchyScratch<float>&, Matrix3X<float>&, float, bool,
                            const ParallelConfig&);
template void run_hierarchy(const HierarchyModel<double>&, HierarchyScratch<double>&, Matrix3X<double>&, double, bool,
                            const ParallelConfig&);
template std::string validate_hierarchy(const HierarchyModel<float>&, const Model<float>&, const Matrix3X<float>*);
template std::string validate_hierarchy(const HierarchyModel<double>&, const Model<double>&, const Matrix3X<double>*);

}  // namespace pbd::detail
