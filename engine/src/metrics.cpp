#include "pbd/metrics.hpp"

#include <algorithm>
#include <cmath>

namespace pbd {
namespace {

struct Accumulator {
  double sum2 = 0.0, max = 0.0;
  std::size_t count = 0;
  void add(double e) {
    sum2 += e * e;
    max = std::max(max, e);
    ++count;
  }
  Violation result() const { return {count ? std::sqrt(sum2 / double(count)) : 0.0, max, count}; }
};

}  // namespace

template <class Real> Violation stretch_violation(const World<Real>& world) {
  const auto x = world.positions();
  Accumulator acc;
  for (const auto& c : world.constraints().stretch) {
    const double len = double((x.col(c.particles[0]) - x.col(c.particles[1])).norm());
    const double d = double(c.rest);
    acc.add(d > 0.0 ? std::abs(len - d) / d : len);
  }
  return acc.result();
}

template <class Real> Violation penetration(const World<Real>& world) {
  const auto x = world.positions();
  const auto w = world.inverse_masses();
  Accumulator acc;
  for (Index i = 0; i < world.num_particles(); ++i) {
    if (w[i] == Real(0)) continue;
    const Eigen::Vector3d p = x.col(i).template cast<double>();
    for (const auto& pl : world.colliders().planes)
      acc.add(std::max(0.0, double(pl.offset) - pl.normal.template cast<double>().dot(p)));
    for (const auto& s : world.colliders().spheres)
      acc.add(std::max(0.0, double(s.radius) - (p - s.center.template cast<double>()).norm()));
  }
  return acc.result();
}

template Violation stretch_violation(const World<float>&);
template Violation stretch_violation(const World<double>&);
template Violation penetration(const World<float>&);
template Violation penetration(const World<double>&);

}  // namespace pbd
