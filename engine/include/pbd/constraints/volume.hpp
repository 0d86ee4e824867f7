#pragma once
/// \file volume.hpp
/// Closed-mesh volume constraint: C = Σ_triangles (p_t1 × p_t2)·p_t3 − pressure(t)·V0 (Müller et al. 2006).
///
/// The sum is six times the enclosed volume; V0 and every volume here are stored in that unit ("6V") so the
/// factor never has to be remembered. A volume constraint spans a whole mesh, so it is not a fixed-arity struct:
/// all volume constraints of a world share one VolumeConstraints table (triangles and, per particle, the ring of
/// triangle corners that make up its gradient), and each has its own projection (project_volumes below, and a
/// parallel one inside the colored solver), both built on the same fixed-shape blocked reduction.
#include "pbd/stiffness.hpp"
#include "pbd/types.hpp"
#include "pbd/violation.hpp"

#include <Eigen/Geometry>
#include <array>
#include <span>
#include <vector>

namespace pbd {

/// How a volume target follows time: pressure(t) = from + (to − from)·min(1, t / duration), then holds `to`.
struct PressureSchedule {
  double from = 1.0;      ///< pressure factor at t = 0
  double to = 1.0;        ///< pressure factor from t = duration on
  double duration = 0.0;  ///< seconds of the linear ramp, ≥ 0 (0: `to` at once)
  /// The pressure factor at time t (seconds since the world started).
  double at(double t) const { return duration > 0.0 && t < duration ? from + (to - from) * (t < 0.0 ? 0.0 : t / duration) : to; }
};

/// One closed mesh's volume constraint; its triangles and gradient rings live in VolumeConstraints.
template <class Real> struct VolumeConstraint {
  static constexpr const char* kName = "volume";  ///< name in reports
  /// Its violation is the relative volume error against the target (metrics.hpp), reported in percent.
  static constexpr Measure kMeasure{"volume_pct", "volume error", "%", 100.0};
  Index set;                           ///< constraint set (stiffness) it belongs to
  Index triangle_begin, triangle_end;  ///< its triangles: VolumeConstraints::triangles[begin, end)
  Index row_begin, row_end;            ///< its particles: VolumeConstraints::particles[begin, end), ascending
  Real rest;                           ///< rest volume V0 in the 6V unit, > 0
  PressureSchedule pressure;           ///< target = pressure.at(t) · rest
};

/// Every volume constraint of a world with the data they span. A "row" is one particle of one constraint.
template <class Real> struct VolumeConstraints {
  std::vector<VolumeConstraint<Real>> items;     ///< the constraints, in insertion order
  std::vector<std::array<Index, 3>> triangles;   ///< all their triangles, counter-clockwise seen from outside
  std::vector<Index> particles;                  ///< the particle of each row
  std::vector<Index> ring_offsets;               ///< row r's ring is ring[ring_offsets[r], ring_offsets[r + 1])
  std::vector<std::array<Index, 2>> ring;        ///< (j, k) per triangle corner of the row's particle i: ∇_i C = Σ p_j × p_k
  std::vector<std::array<Index, 2>> ring_rows;   ///< the same j and k as rows of their constraint (0: its row_begin)

  std::size_t size() const { return items.size(); }  ///< number of volume constraints
  bool empty() const { return items.empty(); }       ///< true when the world has none
  /// Appends one constraint over `tris` (already validated: closed, consistently oriented) and builds its rows.
  void add(std::span<const std::array<Index, 3>> tris, Index set, Real rest, const PressureSchedule& pressure);
};

/// Per-sub-step scratch of the volume projection: targets, gradients of one constraint, block partial sums.
template <class Real> struct VolumeScratch {
  std::vector<Real> target;   ///< current target of each constraint (6V unit)
  std::vector<Real> grad;     ///< 3 per row of the constraint being projected
  std::vector<Real> turned;   ///< 8 per row of that constraint: d = p − o as (d_y d_z d_x 0) and (d_z d_x d_y 0)
  std::vector<Real> partial;  ///< 3 per block: Σ (p − o)·∇C, Σ w|∇C|², Σ w|p − o|⁴
  /// Sets every constraint's target to pressure.at(time) · rest.
  void set_targets(const VolumeConstraints<Real>& v, double time);
};

/// Rows per block of the volume reduction. Blocks are fixed by the mesh, never by the thread count, and their
/// partial sums are added in block order, so a projection gives the same bits serially or on any number of threads.
inline constexpr Index kVolumeBlock = 128;

/// Σ_t (p_t1 × p_t2)·p_t3 over `tris` (six times the enclosed volume), relative to the first corner of the first
/// triangle (for a closed mesh the sum does not depend on the origin; this keeps rounding small far from 0).
template <class Real> Real six_volume(std::span<const std::array<Index, 3>> tris, const Matrix3X<Real>& x);

/// Gauss-Seidel projection of every volume constraint, one after the other, on one thread; λ accumulated in
/// `lambda`. Guards, per constraint: skipped when nothing can move (all particles pinned, α̃ = 0) or when the mesh
/// has collapsed to a line or point (Σ w|∇C|² ≤ (64ε)²·Σ w|p − o|⁴, scale-free); a flat or inverted mesh still has a
/// gradient and is pushed back towards its target.
template <class Real>
void project_volumes(const VolumeConstraints<Real>& v, std::span<const SolveCoefficients<Real>> coeff, Real* p,
                     const Real* w, std::vector<Real>& lambda, VolumeScratch<Real>& scratch);

}  // namespace pbd
