// Phase 2 of the particle contacts (particle_contacts.hpp): the frame the boxes are swept in, what a pair test reads
// of each particle (its mover), and each particle's swept box, summed to size the next sub-step's cells and, when this
// sub-step's cells are known already, classified into level 0's cells in the same pass.
#include "phases.hpp"

#include <algorithm>

namespace pbd::detail::contact {

// The mean path Δ̄ of the contact particles, in fixed chunks.
template <class Real> Vec3<Real> mean_path(Call<Real>& call) {
  ParticleGrid<Real>& g = call.g;
  const Matrix3X<Real>& x = call.x;
  const Matrix3X<Real>& p = call.p;
  const std::vector<Index>& active = call.m.contact.active;
  const Index count = Index(active.size());
  g.partial.resize(kChunks);
  over_chunks(count, call.fork(count), [&](Index ch, Index b, Index e) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Index k = b; k < e; ++k) sum += (p.col(active[k]) - x.col(active[k])).template cast<double>();
    g.partial[ch] = sum;
  });
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (Index ch = 0; ch < std::min<Index>(kChunks, count); ++ch) mean += g.partial[ch];
  return (mean / double(count)).template cast<Real>();
}

// Swept boxes in the frame call.frame (relative paths, all a pair test reads, are the same in any frame that moves with
// a mean path; a falling cloth's boxes stay short there). The pass stores the movers, not the boxes (box_of finds the
// few a later level needs again, the same corners); it keeps the boxes' mean size (the next sub-step's cell widths)
// and mean path (its frame). With the last sub-step's cell widths known, level 0's cells are found here too.
template <class Real> void sweep_boxes(Call<Real>& call) {
  const Model<Real>& m = call.m;
  const ContactBodies<Real>& c = m.contact;
  const Matrix3X<Real>& x = call.x;
  const Matrix3X<Real>& p = call.p;
  const Real margin = call.margin;
  const bool known = call.known;
  const Vec3<Real> shared = call.frame;
  ParticleGrid<Real>& g = call.g;
  const std::vector<Index>& active = c.active;
  const Index count = Index(active.size());
  g.partial.resize(kChunks);
  g.partial_path.resize(kChunks);
  if (g.levels.empty()) g.levels.resize(1);
  Level<Real>& top = g.levels[0];
  top.members.assign(active.begin(), active.end());
  const Vec3<Real> inv0 = g.width.cwiseInverse().template cast<Real>();
  if (known) {
    top.lo.resize(count);
    top.hi.resize(count);
    top.key.resize(count);
    top.bounds.resize(std::min<Index>(kChunks, count));
    top.extent.resize(std::min<Index>(kChunks, count));
  }
  g.movers.resize(m.num_particles());
  over_chunks(count, call.fork(count), [&](Index ch, Index b, Index e) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), path = Eigen::Vector3d::Zero(), large;
    Cell lo, hi;
    open_range(lo, hi, large);
#if defined(__SSE2__)
    if constexpr (std::is_same_v<Real, float>) {  // the same boxes and movers, a particle's three axes at once
      using namespace wide;
      const FloatW frame = lanes(shared[0], shared[1], shared[2], 0.0f);
      const FloatW inv4 = lanes(inv0[0], inv0[1], inv0[2], 0.0f);
      FloatW size4 = zero(), path4 = zero();  // this chunk's sums (they only size the cells)
      for (Index k = b; k < e; ++k) {
        const Index i = active[k];
        const FloatW from = load3(x.data() + 3 * std::size_t(i)), at = load3(p.data() + 3 * std::size_t(i));
        store(g.movers[i].x, with_w(from, c.radius[i]));
        store(g.movers[i].p, with_w(at, m.inverse_mass[i] == 0.0f ? 1.0f : 0.0f));
        FloatW lo4, hi4;
        swept_corners4(from, at, frame, splat(c.radius[i] + 0.5f * margin), lo4, hi4);
        const FloatW size = hi4 - lo4;
        size4 = size4 + size;
        path4 = path4 + (at - from);
        if (known && classify_cells(top, k, cell_of4(lo4, inv4), cell_of4(hi4, inv4), lo, hi)) {
          alignas(16) float extent[4];
          store(extent, size);
          large += Eigen::Vector3d(extent[0], extent[1], extent[2]);
        }
      }
      alignas(16) float sums[2][4];
      store(sums[0], size4);
      store(sums[1], path4);
      sum = Eigen::Vector3d(sums[0][0], sums[0][1], sums[0][2]);
      path = Eigen::Vector3d(sums[1][0], sums[1][1], sums[1][2]);
    } else
#endif
    for (Index k = b; k < e; ++k) {
      const Index i = active[k];
      g.movers[i] = {{x(0, i), x(1, i), x(2, i), c.radius[i]},
                     {p(0, i), p(1, i), p(2, i), m.inverse_mass[i] == Real(0) ? Real(1) : Real(0)}};
      typename ParticleGrid<Real>::Box box;
      swept_corners<Real>(x.col(i), p.col(i), shared, c.radius[i] + Real(0.5) * margin, box.lo, box.hi);
      sum += (box.hi - box.lo).template cast<double>();
      path += (p.col(i) - x.col(i)).template cast<double>();
      if (known) classify(top, k, box, inv0, lo, hi, large);
    }
    g.partial[ch] = sum;
    g.partial_path[ch] = path;
    if (known) {
      top.bounds[ch] = {lo, hi};
      top.extent[ch] = large;
    }
  });
  Eigen::Vector3d extent = Eigen::Vector3d::Zero(), path = Eigen::Vector3d::Zero();
  for (Index ch = 0; ch < std::min<Index>(kChunks, count); ++ch) {
    extent += g.partial[ch];
    path += g.partial_path[ch];
  }
  g.width = kCellScale * extent / double(count);  // for the next sub-step
  g.frame = (path / double(count)).template cast<Real>();
  g.known = count;
}

template Vec3<float> mean_path(Call<float>&);
template Vec3<double> mean_path(Call<double>&);
template void sweep_boxes(Call<float>&);
template void sweep_boxes(Call<double>&);

}  // namespace pbd::detail::contact
