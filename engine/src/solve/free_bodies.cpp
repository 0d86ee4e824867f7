#include "free_bodies.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <numeric>

namespace pbd::detail {
namespace {

Index root(std::vector<Index>& parent, Index i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Adds one particle's mass and moments to a body's 25 sums: mass; first moments of p (q) and x; angular momentum
// about the origin after the solve (q × v_after) and before it (x × v_before); momentum after and before; second
// moments of q (xx, yy, zz, xy, xz, yz).
template <class Real>
inline void add_moments(double* s, double mass, const Real* x, const Real* p, const Real* v, Real h) {
  double q[3], xi[3], before[3], after[3];
  for (int d = 0; d < 3; ++d) {
    const Real predicted = x[d] + h * v[d];  // as steps 2 and 5 compute them
    q[d] = double(p[d]);
    xi[d] = double(x[d]);
    before[d] = double(v[d]);
    after[d] = double(v[d] + (p[d] - predicted) / h);
  }
  const double l_after[3] = {q[1] * after[2] - q[2] * after[1], q[2] * after[0] - q[0] * after[2],
                             q[0] * after[1] - q[1] * after[0]};
  const double l_before[3] = {xi[1] * before[2] - xi[2] * before[1], xi[2] * before[0] - xi[0] * before[2],
                              xi[0] * before[1] - xi[1] * before[0]};
  s[0] += mass;
  for (int d = 0; d < 3; ++d) {
    s[1 + d] += mass * q[d];
    s[4 + d] += mass * xi[d];
    s[7 + d] += mass * l_after[d];
    s[10 + d] += mass * l_before[d];
    s[13 + d] += mass * after[d];
    s[16 + d] += mass * before[d];
  }
  s[19] += mass * q[0] * q[0];
  s[20] += mass * q[1] * q[1];
  s[21] += mass * q[2] * q[2];
  s[22] += mass * q[0] * q[1];
  s[23] += mass * q[0] * q[2];
  s[24] += mass * q[1] * q[2];
}

}  // namespace

template <class Real> void update_free_bodies(const Model<Real>& m, FreeBodies<Real>& f) {
  if (f.edits == m.edits && Index(f.body.size()) == m.num_particles()) return;
  const Index n = m.num_particles();
  std::vector<Index> parent(n);
  std::iota(parent.begin(), parent.end(), Index(0));
  std::vector<std::uint8_t> linked(n, 0), held(n, 0);
  auto join = [&](Index a, Index b) {
    linked[a] = linked[b] = 1;
    const Index ra = root(parent, a), rb = root(parent, b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  };
  // Every type, built-in or user-defined: its constraints join their particles into bodies; a type tied to the
  // world (anchors) holds them.
  for_each_type(m, [&](const TypeStore<Real>& t, std::size_t) {
    t.join_particles(join);
    t.mark_held(held);
  });
  const auto& v = m.volume.table;
  for (const auto& c : v.items)
    for (Index r = c.row_begin + 1; r < c.row_end; ++r) join(v.particles[c.row_begin], v.particles[r]);
  for (Index i = 0; i < n; ++i)
    if (m.inverse_mass[i] == Real(0)) held[i] = 1;
  // A root is held when any of its particles is; bodies numbered by first particle.
  std::vector<std::uint8_t> root_held(n, 0);
  for (Index i = 0; i < n; ++i)
    if (held[i]) root_held[root(parent, i)] = 1;
  std::vector<Index> id(n, FreeBodies<Real>::kNone);
  f.body.assign(n, FreeBodies<Real>::kNone);
  f.count = 0;
  for (Index i = 0; i < n; ++i) {
    if (!linked[i]) continue;
    const Index r = root(parent, i);
    if (root_held[r]) continue;
    if (id[r] == FreeBodies<Real>::kNone) id[r] = f.count++;
    f.body[i] = id[r];
  }
  f.edits = m.edits;
}

template <class Real>
bool find_free_contacts(FreeBodies<Real>& f, std::span<const CollisionConstraint<Real>> contacts,
                        std::span<const ParticleContact<Real>> pairs) {
  if (f.count == 0) return false;
  constexpr Index kNone = FreeBodies<Real>::kNone;
  // Contacts: none (0), all along one normal n (1: their forces have no torque about n through any point, so the
  // body keeps L·n), or along several (2: the body is left alone).
  f.contact.assign(f.count, 0);
  f.normal.resize(3 * std::size_t(f.count));
  for (const auto& c : pairs)  // another body's push, or the body's own against itself: left alone
    for (Index i : c.particles)
      if (f.body[i] != kNone) f.contact[f.body[i]] = 2;
  for (const auto& c : contacts) {
    const Index b = f.body[c.particles[0]];
    if (b == kNone || f.contact[b] == 2) continue;
    if (c.material.static_friction != Real(0) || c.material.kinetic_friction != Real(0)) {
      f.contact[b] = 2;  // friction pushes along the surface: a torque about n
      continue;
    }
    double* n = f.normal.data() + 3 * std::size_t(b);
    if (f.contact[b] == 0) {
      f.contact[b] = 1;
      for (int d = 0; d < 3; ++d) n[d] = double(c.normal[d]);
    } else if (n[0] != double(c.normal[0]) || n[1] != double(c.normal[1]) || n[2] != double(c.normal[2])) {
      f.contact[b] = 2;
    }
  }
  bool any = false;
  for (Index b = 0; b < f.count; ++b) any = any || f.contact[b] != 2;
  if (any) f.parts.resize(std::size_t((Index(f.body.size()) + kSpinChunk - 1) / kSpinChunk));
  return any;
}

template <class Real>
void sum_free_chunk(const Model<Real>& m, FreeBodies<Real>& f, Index chunk, const Real* x, const Real* p, const Real* v,
                    Real h) {
  constexpr Index kNone = FreeBodies<Real>::kNone;
  auto& parts = f.parts[chunk];
  parts.clear();
  const Index end = std::min(m.num_particles(), (chunk + 1) * kSpinChunk);
  for (Index i = chunk * kSpinChunk; i < end;) {
    const Index b = f.body[i];
    if (b == kNone || f.contact[b] == 2) {
      ++i;
      continue;
    }
    // A run of the body's particles, summed in locals (registers, not stores through memory) in particle order.
    double a[kSpinSums] = {};
    for (; i < end && f.body[i] == b; ++i) add_moments<Real>(a, 1.0 / double(m.inverse_mass[i]), x + 3 * std::size_t(i),
                                                             p + 3 * std::size_t(i), v + 3 * std::size_t(i), h);
    parts.push_back({b, {}});
    std::copy(a, a + kSpinSums, parts.back().sums.begin());
  }
}

template <class Real> bool find_solver_spin(FreeBodies<Real>& f) {
  constexpr int kSums = kSpinSums;
  f.sums.assign(std::size_t(f.count) * kSums, 0.0);
  for (const auto& chunk : f.parts)  // chunk order, then run order: the same bits however the chunks were shared
    for (const auto& run : chunk) {
      double* s = f.sums.data() + std::size_t(run.body) * kSums;
      for (int k = 0; k < kSums; ++k) s[k] += run.sums[k];
    }
  f.omega.assign(std::size_t(f.count) * 9, std::numeric_limits<double>::quiet_NaN());
  bool any = false;
  for (Index b = 0; b < f.count; ++b) {
    if (f.contact[b] == 2) continue;
    const double* s = f.sums.data() + std::size_t(b) * kSums;
    const double mass = s[0];
    auto v3 = [&](int k) { return Eigen::Vector3d(s[k], s[k + 1], s[k + 2]); };
    const Eigen::Vector3d c = v3(1) / mass, c_before = v3(4) / mass;
    // Angular momentum about the centre of mass after the solve and before it (after forces and damping).
    const Eigen::Vector3d l = (v3(7) - c.cross(v3(13))) - (v3(10) - c_before.cross(v3(16)));
    Eigen::Matrix3d second;  // Σ m (p − c)(p − c)ᵀ
    second << s[19], s[22], s[23], s[22], s[20], s[24], s[23], s[24], s[21];
    second -= mass * c * c.transpose();
    const Eigen::Matrix3d inertia = second.trace() * Eigen::Matrix3d::Identity() - second;
    // A body on a line (or a point) has no inertia about it: leave such a body alone.
    Eigen::Vector3d w;
    if (f.contact[b] == 1) {  // only the rotation about n
      const Eigen::Vector3d n(f.normal[3 * b], f.normal[3 * b + 1], f.normal[3 * b + 2]);
      const double about_n = n.dot(inertia * n);
      if (!(about_n > 1e-9 * inertia.trace())) continue;
      w = n * (n.dot(l) / about_n);
    } else {
      Eigen::LDLT<Eigen::Matrix3d> ldlt(inertia);
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-9 * inertia.trace())) continue;
      w = ldlt.solve(l);
    }
    // Linear momentum: the solve's projections conserve it, up to rounding, which in float adds up where
    // conflicting constraints make large corrections every step; give it back too (along the contacts' normal,
    // the contacts' push is real).
    Eigen::Vector3d shift = (v3(13) - v3(16)) / mass;
    if (f.contact[b] == 1) {
      const Eigen::Vector3d n(f.normal[3 * b], f.normal[3 * b + 1], f.normal[3 * b + 2]);
      shift -= n * n.dot(shift);
    }
    for (int d = 0; d < 3; ++d) {
      f.omega[9 * std::size_t(b) + d] = w[d];
      f.omega[9 * std::size_t(b) + 3 + d] = c[d];
      f.omega[9 * std::size_t(b) + 6 + d] = shift[d];
    }
    any = true;
  }
  return any;
}

template void update_free_bodies(const Model<float>&, FreeBodies<float>&);
template void update_free_bodies(const Model<double>&, FreeBodies<double>&);
template bool find_free_contacts(FreeBodies<float>&, std::span<const CollisionConstraint<float>>,
                                 std::span<const ParticleContact<float>>);
template bool find_free_contacts(FreeBodies<double>&, std::span<const CollisionConstraint<double>>,
                                 std::span<const ParticleContact<double>>);
template void sum_free_chunk(const Model<float>&, FreeBodies<float>&, Index, const float*, const float*, const float*,
                             float);
template void sum_free_chunk(const Model<double>&, FreeBodies<double>&, Index, const double*, const double*,
                             const double*, double);
template bool find_solver_spin(FreeBodies<float>&);
template bool find_solver_spin(FreeBodies<double>&);

}  // namespace pbd::detail
