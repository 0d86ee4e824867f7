// The particle contacts' broad phase (engine/src/contact/particle_contacts.hpp) against brute force: on random
// layouts that take each of its paths (a dense cluster: the dense grid; particles scattered over a wide space: the
// hash table; a few particles far faster than the rest: boxes paired with every box; a third of the particles a few
// times faster: grids of wider cells for them; self-colliding bodies whose joined pairs are excluded (also when a
// particle is joined to dozens of particles within reach); pinned
// particles; hundreds of boxes in one cell: more candidates than a particle's batch holds), it finds exactly the pairs whose relative path comes within
// r_a + r_b + margin, each once, in the order of the pairs, and the same list with and without threads, and from a
// grid that kept another sub-step's frame and cells.
#include "contact/particle_contacts.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace pbd::detail {
namespace {

struct Layout {
  const char* name;
  int particles;
  double spread;      // positions uniform in a cube of this side, m
  double step;        // paths uniform in a cube of this side, m
  int fast;           // particles whose paths are `faster` times longer (larger boxes)
  int clusters = 0;   // > 0: particles in this many clusters 0.3 m wide, placed at random in the cube
  bool self = false;  // one self-colliding body whose consecutive particles are joined by stretch constraints
  double faster = 1000;
  double width = 0.3;  // of a cluster, m
  int joins = 0;       // self: > 0, each particle joined to the next `joins` of its cluster (else to one neighbour)
};

template <class Real> struct Case {
  Model<Real> model;
  Matrix3X<Real> x, p, v;
};

template <class Real> Case<Real> make(const Layout& l, std::uint32_t seed) {
  Case<Real> c;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const Index n = l.particles;
  c.model.inverse_mass = VectorX<Real>::Ones(n);
  c.x.resize(3, n);
  c.p.resize(3, n);
  c.v = Matrix3X<Real>::Zero(3, n);
  std::vector<Eigen::Vector3d> centres(std::max(1, l.clusters), Eigen::Vector3d::Zero());
  if (l.clusters > 0)
    for (auto& centre : centres) centre = Eigen::Vector3d(u(rng), u(rng), u(rng)) * l.spread;
  for (Index i = 0; i < n; ++i) {
    const double scale = i < Index(l.fast) ? l.faster : 1.0;
    for (int d = 0; d < 3; ++d) {
      c.x(d, i) = Real(l.clusters > 0 ? centres[i % l.clusters][d] + l.width * u(rng) : l.spread * u(rng));
      c.p(d, i) = Real(double(c.x(d, i)) + l.step * scale * u(rng) + 0.3 * l.step);  // a shared drift
    }
    if (i % 17 == 5) c.model.inverse_mass[i] = 0;  // pinned (two pinned particles never touch)
  }
  if (l.self) {
    c.model.contact.bodies.push_back({0, n, Real(0.01), ContactMaterial<Real>{}, true});
    auto& stretch = c.model.template store<StretchConstraint<Real>>().items;
    if (l.joins == 0)
      for (Index i = 0; i + 1 < n; i += 2) stretch.push_back({{i, i + 1}, 0, Real(0.02)});
    const Index stride = Index(std::max(1, l.clusters));  // particle i is in cluster i % clusters
    for (Index i = 0; i < n; ++i)
      for (Index k = 1; k <= Index(l.joins) && i + k * stride < n; ++k)
        stretch.push_back({{i, i + k * stride}, 0, Real(0.02)});
  } else {  // three bodies of different radii; the last has none (it touches nothing)
    const Index a = n / 2, b = n / 4;
    c.model.contact.bodies.push_back({0, a, Real(0.01), ContactMaterial<Real>{}, false});
    c.model.contact.bodies.push_back({a, b, Real(0.02), ContactMaterial<Real>{}, false});
    c.model.contact.bodies.push_back({a + b, n - a - b, Real(0), ContactMaterial<Real>{}, false});
  }
  c.model.edits = 1;
  cook_contact_bodies(c.model);
  return c;
}

// Pairs (a < b) whose relative path (x_a − x_b) → (p_a − p_b) comes within r_a + r_b + margin, from every pair,
// in double: the same criterion the broad phase applies, without its grid.
template <class Real> std::set<std::pair<Index, Index>> brute_force(const Case<Real>& c, double margin) {
  std::set<std::pair<Index, Index>> pairs, joined;
  for (const auto& con : c.model.template store<StretchConstraint<Real>>().items)
    joined.insert(std::minmax(con.particles[0], con.particles[1]));
  const ContactBodies<Real>& cb = c.model.contact;
  const Index n = c.model.num_particles();
  for (Index a = 0; a < n; ++a)
    for (Index b = a + 1; b < n; ++b) {
      if (cb.radius[a] == Real(0) || cb.radius[b] == Real(0)) continue;
      if (c.model.inverse_mass[a] == Real(0) && c.model.inverse_mass[b] == Real(0)) continue;
      if (cb.body_of[a] == cb.body_of[b] && !cb.bodies[cb.body_of[a]].self_collision) continue;
      if (joined.count({a, b}) > 0) continue;  // joined by a stretch constraint (self-colliding bodies)
      const Eigen::Vector3d d0 = (c.x.col(a) - c.x.col(b)).template cast<double>();
      const Eigen::Vector3d d1 = (c.p.col(a) - c.p.col(b)).template cast<double>();
      const Eigen::Vector3d e = d1 - d0;
      const double t = e.squaredNorm() > 0 ? std::clamp(-d0.dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
      const double R = double(cb.radius[a] + cb.radius[b]) + margin;
      if ((d0 + t * e).squaredNorm() < R * R) pairs.insert({a, b});
    }
  return pairs;
}

template <class Real> class ParticleContacts : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(ParticleContacts, Precisions);

TYPED_TEST(ParticleContacts, FindExactlyThePairsWhosePathsComeWithinReach) {
  using Real = TypeParam;
  const Layout layouts[] = {
      {"dense cluster", 5000, 0.5, 0.01, 0},
      {"clusters far apart (hash table)", 2000, 20.0, 0.01, 0, 5},
      {"a few far faster", 2000, 0.6, 0.01, 5},
      {"a third faster (grids of wider cells)", 3000, 0.6, 0.01, 1000, 0, false, 6},
      {"self-colliding, joined pairs", 3000, 0.5, 0.01, 0, 0, true},
      {"still", 1500, 0.4, 0.0, 0},
      {"crowded cells (hundreds of boxes in a cell)", 900, 0.5, 0.001, 0, 3, false, 1000, 0.01},
      // each particle joined to 24 others within reach: more than the first groups of its row of joined particles
      // hold (joined_bits), so the rest of the row decides
      {"crowded, self-colliding, many joined pairs", 900, 0.5, 0.001, 0, 3, true, 1000, 0.01, 12},
  };
  const double margin = 0.004;
  for (const Layout& l : layouts)
    for (std::uint32_t seed : {1u, 2u, 3u}) {
      SCOPED_TRACE(std::string(l.name) + " seed " + std::to_string(seed));
      Case<Real> c = make<Real>(l, seed);
      const auto expected = brute_force(c, margin);
      ParticleGrid<Real> grid;
      std::vector<ParticleContact<Real>> found;
      generate_particle_contacts(c.model, c.x, c.p, c.v, Real(margin), false, grid, found);
      std::set<std::pair<Index, Index>> got;
      std::size_t near_boundary = 0;  // float rounding may decide a pair within 1e-5 of reach either way
      for (std::size_t k = 1; k < found.size(); ++k)  // in the order of the pairs, whatever the grid
        ASSERT_LT(found[k - 1].particles, found[k].particles) << k;
      for (const auto& k : found) {
        ASSERT_LT(k.particles[0], k.particles[1]);
        EXPECT_TRUE(got.insert({k.particles[0], k.particles[1]}).second)
            << "pair " << k.particles[0] << "-" << k.particles[1] << " found twice";
      }
      std::vector<std::pair<Index, Index>> missing, extra;
      std::set_difference(expected.begin(), expected.end(), got.begin(), got.end(), std::back_inserter(missing));
      std::set_difference(got.begin(), got.end(), expected.begin(), expected.end(), std::back_inserter(extra));
      auto at_reach = [&](const std::pair<Index, Index>& q) {
        const ContactBodies<Real>& cb = c.model.contact;
        const Eigen::Vector3d d0 = (c.x.col(q.first) - c.x.col(q.second)).template cast<double>();
        const Eigen::Vector3d d1 = (c.p.col(q.first) - c.p.col(q.second)).template cast<double>();
        const Eigen::Vector3d e = d1 - d0;
        const double t = e.squaredNorm() > 0 ? std::clamp(-d0.dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
        const double R = double(cb.radius[q.first] + cb.radius[q.second]) + margin;
        return std::abs((d0 + t * e).norm() - R) < 1e-5 * (1 + R);
      };
      for (const auto& q : missing) near_boundary += at_reach(q) ? 1 : 0;
      for (const auto& q : extra) near_boundary += at_reach(q) ? 1 : 0;
      EXPECT_EQ(missing.size() + extra.size(), near_boundary)
          << missing.size() << " pairs missed, " << extra.size() << " extra, of " << expected.size();
      EXPECT_GT(expected.size(), std::size_t(l.particles) / 20) << "the layout must have contacts to find";
      // the same list, in the same order, with the loops run in parallel
      std::vector<ParticleContact<Real>> again;
      ParticleGrid<Real> grid2;
      tbb::task_arena(2).execute(
          [&] { generate_particle_contacts(c.model, c.x, c.p, c.v, Real(margin), true, grid2, again); });
      ASSERT_EQ(again.size(), found.size());
      for (std::size_t k = 0; k < found.size(); ++k) EXPECT_EQ(again[k].particles, found[k].particles) << k;
      // the same list from a grid that kept another sub-step's frame and cell widths (paths three times as long and
      // moved: another mean path, wider boxes), and again from one that kept this sub-step's
      ParticleGrid<Real> grid3;
      std::vector<ParticleContact<Real>> other, third, fourth;
      Matrix3X<Real> moved = c.x + Real(3) * (c.p - c.x);
      moved.colwise() += Vec3<Real>(Real(0.05), Real(-0.02), Real(0.1));
      generate_particle_contacts(c.model, c.x, moved, c.v, Real(margin), false, grid3, other);
      generate_particle_contacts(c.model, c.x, c.p, c.v, Real(margin), false, grid3, third);
      generate_particle_contacts(c.model, c.x, c.p, c.v, Real(margin), false, grid3, fourth);
      ASSERT_EQ(third.size(), found.size());
      ASSERT_EQ(fourth.size(), found.size());
      for (std::size_t k = 0; k < found.size(); ++k) {
        EXPECT_EQ(third[k].particles, found[k].particles) << k;
        EXPECT_EQ(fourth[k].particles, found[k].particles) << k;
      }
    }
}

}  // namespace
}  // namespace pbd::detail
