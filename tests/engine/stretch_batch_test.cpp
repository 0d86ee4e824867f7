// The blocked stretch kernel of the colored sweep gives bit for bit what the generic projection gives.
#include "pbd/constraints/projection.hpp"
#include "stretch_batch.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace pbd {
namespace {

template <class Real> void check(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const int m = 37;  // constraints on disjoint particle pairs (one color), not a multiple of the block size
  std::vector<StretchConstraint<Real>> c;
  std::vector<Real> p(3 * 2 * m), w(2 * m), lam_a(m), lam_b(m);
  for (auto& x : p) x = Real(u(rng));
  for (int i = 0; i < 2 * m; ++i) w[i] = i % 5 == 0 ? Real(0) : Real(0.1 + std::abs(u(rng)));
  for (int i = 0; i < m; ++i) {
    c.push_back({{Index(2 * i), Index(2 * i + 1)}, Index(i % 2), Real(std::abs(u(rng)))});
    lam_a[i] = lam_b[i] = Real(u(rng) * 1e-3);
  }
  // Guards: coincident particles, an all-pinned pair.
  for (int d = 0; d < 3; ++d) p[3 * 7 + d] = p[3 * 6 + d];
  w[10] = w[11] = Real(0);
  const std::vector<SolveCoefficients<Real>> coeff = {{Real(0.8), Real(0)}, {Real(1), Real(2.5)}};
  std::vector<Real> q = p;
  for (int sweep = 0; sweep < 3; ++sweep) {
    for (int i = 0; i < m; ++i) project(c[i], p.data(), w.data(), coeff[c[i].set], lam_a[i]);
    detail::project_stretch_range(c.data(), 0, Index(m), q.data(), w.data(), coeff.data(), lam_b.data());
  }
  EXPECT_EQ(std::memcmp(p.data(), q.data(), p.size() * sizeof(Real)), 0);
  EXPECT_EQ(std::memcmp(lam_a.data(), lam_b.data(), m * sizeof(Real)), 0);
  for (Real x : q) EXPECT_TRUE(std::isfinite(x));
}

TEST(StretchBatch, BitwiseEqualToTheGenericProjectionFloat) {
  for (unsigned s = 1; s <= 20; ++s) check<float>(s);
}
TEST(StretchBatch, BitwiseEqualToTheGenericProjectionDouble) {
  for (unsigned s = 1; s <= 20; ++s) check<double>(s);
}

}  // namespace
}  // namespace pbd
