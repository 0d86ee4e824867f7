#pragma once
/// \file violation.hpp
/// How far constraints are from holding: the one violation type of step statistics, error measures and the study,
/// and how each type's violation is reported (Measure: declared in the type's header, e.g. stretch.hpp).
#include "pbd/types.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>

namespace pbd {

/// Read-only view of 3×N positions (a Matrix3X or the map World::positions() returns), no copy.
/// (Non-deduced, so Real comes from the constraint and any matrix or map converts.)
template <class Real> using PositionsView = std::type_identity_t<Eigen::Ref<const Matrix3X<Real>>>;

/// How one constraint type's violation is reported (the error measures of `pbd study`, its plots): the reported
/// value is violation × scale, in `unit`.
struct Measure {
  const char* key = "";    ///< the error's key in reports, e.g. "stretch_pct"
  const char* label = "";  ///< what it measures, e.g. "stretch" (plots say "RMS stretch (%)")
  const char* unit = "";   ///< the reported unit, e.g. "%"
  double scale = 1.0;      ///< factor from the violation's own unit (a fraction, m, rad) to `unit`
};

/// RMS and maximum of a normalized violation over the constraints of one type (0 and 0 when there are none); the
/// per-type normalizations are listed in metrics.hpp.
struct Violation {
  double rms = 0.0;        ///< root mean square
  double max = 0.0;        ///< maximum
  std::size_t count = 0;   ///< constraints measured
};

/// The violation of one constraint type, named as the type's kName ("stretch", ..., "volume", "collision").
struct NamedViolation {
  std::string type;  ///< constraint type
  Violation value;   ///< its RMS, maximum and count
  Measure measure;   ///< how it is reported (the type's kMeasure)
};

/// Sums squares and keeps the maximum, in double: the one accumulator behind every Violation.
struct ViolationAccumulator {
  double sum2 = 0.0;      ///< Σ e²
  double max = 0.0;       ///< max e
  std::size_t count = 0;  ///< items added
  /// Adds one item's violation e ≥ 0.
  void add(double e) {
    sum2 += e * e;
    max = std::max(max, e);
    ++count;
  }
  /// Adds a whole Violation (its count items with its RMS and maximum).
  void add(const Violation& v) {
    sum2 += v.rms * v.rms * double(v.count);
    max = std::max(max, v.max);
    count += v.count;
  }
  /// RMS, maximum and count of what was added.
  Violation result() const { return {count ? std::sqrt(sum2 / double(count)) : 0.0, max, count}; }
};

namespace detail {
/// Position of particle i as a double vector (every violation is measured in double).
template <class Real> Eigen::Vector3d position_of(const PositionsView<Real>& x, Index i) {
  return x.col(Eigen::Index(i)).template cast<double>();
}
/// |value − rest| / rest, or |value| where rest = 0.
inline double relative_error(double value, double rest) {
  return rest > 0.0 ? std::abs(value - rest) / rest : std::abs(value);
}
}  // namespace detail

}  // namespace pbd
