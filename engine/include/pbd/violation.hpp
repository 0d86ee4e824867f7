#pragma once
/// \file violation.hpp
/// How far constraints are from holding: the one violation type of step statistics, error measures and the study.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

namespace pbd {

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

}  // namespace pbd
