#include "pbd/constraints/volume.hpp"

#include "solve/volume_projection.hpp"

#include <algorithm>

namespace pbd {

template <class Real>
void VolumeConstraints<Real>::add(std::span<const std::array<Index, 3>> tris, Index set, Real rest,
                                  const PressureSchedule& pressure) {
  VolumeConstraint<Real> c{set, Index(triangles.size()), Index(triangles.size() + tris.size()), Index(particles.size()),
                           0, rest, pressure};
  triangles.insert(triangles.end(), tris.begin(), tris.end());
  // Rows: the constraint's particles in ascending order; each row's ring lists, per triangle corner it sits at, the
  // next two corners in winding order (for triangle (a, b, c): ∂/∂a = b × c, ∂/∂b = c × a, ∂/∂c = a × b).
  std::vector<std::pair<Index, std::array<Index, 2>>> corners;
  corners.reserve(3 * tris.size());
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) corners.push_back({t[k], {t[(k + 1) % 3], t[(k + 2) % 3]}});
  std::stable_sort(corners.begin(), corners.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  if (ring_offsets.empty()) ring_offsets.push_back(0);
  for (std::size_t k = 0; k < corners.size(); ++k) {
    if (k == 0 || corners[k].first != corners[k - 1].first) {
      if (k > 0) ring_offsets.push_back(Index(ring.size()));
      particles.push_back(corners[k].first);
    }
    ring.push_back(corners[k].second);
  }
  if (!corners.empty()) ring_offsets.push_back(Index(ring.size()));
  c.row_end = Index(particles.size());
  // Each ring corner as a row of this constraint (every corner of its triangles is one of its rows).
  const auto rows_begin = particles.begin() + c.row_begin, rows_end = particles.begin() + c.row_end;
  auto row_of = [&](Index particle) { return Index(std::lower_bound(rows_begin, rows_end, particle) - rows_begin); };
  for (std::size_t k = ring_rows.size(); k < ring.size(); ++k) ring_rows.push_back({row_of(ring[k][0]), row_of(ring[k][1])});
  items.push_back(c);
}

template <class Real> void VolumeScratch<Real>::set_targets(const VolumeConstraints<Real>& v, double time) {
  target.resize(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) target[i] = Real(v.items[i].pressure.at(time)) * v.items[i].rest;
}

template <class Real> Real six_volume(std::span<const std::array<Index, 3>> tris, const Matrix3X<Real>& x) {
  if (tris.empty()) return Real(0);
  const Vec3<Real> o = x.col(tris[0][0]);
  Real sum = 0;
  for (const auto& t : tris)
    sum += Vec3<Real>(x.col(t[0]) - o).cross(Vec3<Real>(x.col(t[1]) - o)).dot(Vec3<Real>(x.col(t[2]) - o));
  return sum;
}

template <class Real>
void project_volumes(const VolumeConstraints<Real>& v, std::span<const SolveCoefficients<Real>> coeff, Real* p,
                     const Real* w, std::vector<Real>& lambda, VolumeScratch<Real>& scratch) {
  if (scratch.target.size() != v.size()) scratch.set_targets(v, 0.0);
  auto serial = [](Index b, Index e, const auto& body) { body(b, e); };
  for (Index i = 0; i < Index(v.size()); ++i)
    detail::project_volume(v, i, p, p, w, coeff[v.items[i].set], scratch.target[i], lambda[i], scratch, serial);
}

template struct VolumeConstraints<float>;
template struct VolumeConstraints<double>;
template struct VolumeScratch<float>;
template struct VolumeScratch<double>;
template float six_volume(std::span<const std::array<Index, 3>>, const Matrix3X<float>&);
template double six_volume(std::span<const std::array<Index, 3>>, const Matrix3X<double>&);
template void project_volumes(const VolumeConstraints<float>&, std::span<const SolveCoefficients<float>>, float*,
                              const float*, std::vector<float>&, VolumeScratch<float>&);
template void project_volumes(const VolumeConstraints<double>&, std::span<const SolveCoefficients<double>>, double*,
                              const double*, std::vector<double>&, VolumeScratch<double>&);

}  // namespace pbd
