#pragma once
// Swept boxes and their cells (private to contact/): the boxes' pass (boxes.cpp) and the later levels (grid.cpp,
// walk.cpp) find a box's corners, its cells and its class (small, in pieces, large) with these same functions, so a
// box found again from its mover has the corners and cells the boxes' pass gave it.
#include "particle_contacts.hpp"

#include "simd/wide.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace pbd::detail::contact {

using Cell = std::array<std::int32_t, 3>;

constexpr std::uint32_t kLarge = ~std::uint32_t(0);
constexpr std::uint32_t kSplit = kLarge - 1;  // a box entered as a few small ones (particle_contacts.hpp, phase 3)
constexpr int kMaxPieces = 4;                 // pieces a box is entered as at most (else it is large)

#if defined(__SSE2__)
// The cells of q (lanes 0-2) with widths 1/inv: floor(q·inv), clamped, three axes at once.
inline Cell cell_of4(wide::FloatW q, wide::FloatW inv) {
  using namespace wide;
  alignas(16) std::int32_t out[4];
  store(out, floor_to_int(max(min(q * inv, splat(1e9f)), splat(-1e9f))));
  return {out[0], out[1], out[2]};
}
#endif

template <class Real> inline Cell cell_of(const Vec3<Real>& q, const Vec3<Real>& inv) {
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Real, float>)  // the same cells, three axes at once
    return cell_of4(wide::lanes(q[0], q[1], q[2], 0.0f), wide::lanes(inv[0], inv[1], inv[2], 0.0f));
#endif
  auto axis = [&](int d) {  // clamped so that a far particle cannot overflow (it only shares a cell more often);
    const Real v = std::floor(q[d] * inv[d]);  // a NaN (a blown-up state) goes to the lowest cell, not to an
    return std::int32_t(v >= Real(1e9) ? Real(1e9) : v > Real(-1e9) ? v : Real(-1e9));  // undefined conversion
  };
  return {axis(0), axis(1), axis(2)};
}

#if defined(__SSE2__)
// A float path's swept box: from x and p (lanes 0-2; lane 3 is ignored) in the frame moving with `frame`, grown by
// `grow` (lo, hi). The boxes' pass and box_of both call it: the same corners.
inline void swept_corners4(wide::FloatW from, wide::FloatW at, wide::FloatW frame, wide::FloatW grow, wide::FloatW& lo,
                           wide::FloatW& hi) {
  const wide::FloatW to = at - frame;
  lo = min(from, to) - grow;
  hi = max(from, to) + grow;
}
#endif

// The same for any Real, an axis at a time (the corners of the float path's box for float).
template <class Real>
inline void swept_corners(const Vec3<Real>& from, const Vec3<Real>& at, const Vec3<Real>& frame, Real grow, Vec3<Real>& lo,
                          Vec3<Real>& hi) {
  const Vec3<Real> to = at - frame;
  lo = from.cwiseMin(to).array() - grow;
  hi = from.cwiseMax(to).array() + grow;
}

// Particle i's swept box, found again from its mover as the boxes' pass found it (only the few boxes of the levels
// after the first and the large ones need it: no pass stores them).
template <class Real>
inline typename ParticleGrid<Real>::Box box_of(const ParticleGrid<Real>& g, Index i, const Vec3<Real>& frame, Real margin) {
  typename ParticleGrid<Real>::Box box;
  const auto& a = g.movers[i];
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Real, float>) {
    using namespace wide;
    FloatW lo4, hi4;
    swept_corners4(load(a.x), load(a.p), lanes(frame[0], frame[1], frame[2], 0.0f), splat(a.x[3] + 0.5f * margin), lo4,
                   hi4);
    alignas(16) float corner[2][4];
    store(corner[0], lo4);
    store(corner[1], hi4);
    box.lo = Vec3<Real>(corner[0][0], corner[0][1], corner[0][2]);
    box.hi = Vec3<Real>(corner[1][0], corner[1][1], corner[1][2]);
    return box;
  }
#endif
  swept_corners<Real>(Vec3<Real>(a.x[0], a.x[1], a.x[2]), Vec3<Real>(a.p[0], a.p[1], a.p[2]), frame,
                      a.x[3] + Real(0.5) * margin, box.lo, box.hi);
  return box;
}

inline std::uint32_t hash_cell(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t mask) {
  const std::uint64_t h = std::uint64_t(x) * 73856093ull ^ std::uint64_t(y) * 19349663ull ^ std::uint64_t(z) * 83492791ull;
  return std::uint32_t((h ^ (h >> 29)) & mask);
}

// A chunk's start: no lower cells yet (lo, hi) and no large box's size summed.
inline void open_range(Cell& lo, Cell& hi, Eigen::Vector3d& sum) {
  constexpr std::int32_t top = std::numeric_limits<std::int32_t>::max(), bottom = std::numeric_limits<std::int32_t>::min();
  lo = {top, top, top};
  hi = {bottom, bottom, bottom};
  sum.setZero();
}

// A box's cells (its lower and upper corners' a, z), as the level's member k: small (0), in pieces (kSplit) or large
// (kLarge); an entry's lower cells widen [lo, hi]. True when large (its size then adds to the chunk's sum).
template <class Level>
inline bool classify_cells(Level& lv, Index k, const Cell& a, const Cell& z, Cell& lo, Cell& hi) {
  lv.lo[k] = a;
  lv.hi[k] = z;
  // pieces along each axis: blocks of two cells from the lower corner's (cells are clamped to ±1e9: no
  // overflow)
  const std::int32_t sx = z[0] - a[0], sy = z[1] - a[1], sz = z[2] - a[2];
  Cell top_corner = a;  // the last piece's lower corner
  int pieces = 1;
  if ((sx | sy | sz) > 1) {
    const std::int32_t span[3] = {sx, sy, sz};
    for (int d = 0; d < 3; ++d) {
      const int along = span[d] <= 1 ? 1 : span[d] <= 3 ? 2 : kMaxPieces + 1;
      pieces *= along;
      top_corner[d] = a[d] + 2 * (along - 1);
    }
  }
  lv.key[k] = pieces == 1 ? 0 : pieces <= kMaxPieces ? kSplit : kLarge;
  if (pieces > kMaxPieces) return true;
  for (int d = 0; d < 3; ++d) {
    lo[d] = std::min(lo[d], a[d]);
    hi[d] = std::max(hi[d], top_corner[d]);
  }
  return false;
}

// The same from the box, with cells of widths 1/inv; a large box's size adds to `sum`.
template <class Level, class Box, class Real>
inline void classify(Level& lv, Index k, const Box& box, const Vec3<Real>& inv, Cell& lo, Cell& hi, Eigen::Vector3d& sum) {
  if (classify_cells(lv, k, cell_of<Real>(box.lo, inv), cell_of<Real>(box.hi, inv), lo, hi))
    sum += (box.hi - box.lo).template cast<double>();
}

}  // namespace pbd::detail::contact
