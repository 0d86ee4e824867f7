#include "colliders.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>

namespace pbd {
namespace {

// First parameter t in [0, 1] at which the segment x + t·d enters the ball (|y − c| ≤ r), or -1 if it never does.
// x is outside the ball.
template <class Real> Real entry_parameter(const Vec3<Real>& x, const Vec3<Real>& d, const Sphere<Real>& s) {
  const Vec3<Real> m = x - s.center;
  const Real a = d.squaredNorm();
  if (!(a > Real(0))) return Real(-1);
  const Real b = m.dot(d);
  const Real c = m.squaredNorm() - s.radius * s.radius;
  const Real disc = b * b - a * c;
  if (disc < Real(0)) return Real(-1);
  const Real t = (-b - std::sqrt(disc)) / a;
  return (t >= Real(0) && t <= Real(1)) ? t : Real(-1);
}

// The collisions of particles [begin, end), appended to `out` in order.
template <class Real>
void collide_range(const Colliders<Real>& colliders, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                   const Matrix3X<Real>& v, const VectorX<Real>& w, Real margin, ParticleSurfaces<Real> surfaces,
                   Index begin, Index end, std::vector<CollisionConstraint<Real>>& out) {
  for (Index i = begin; i < end; ++i) {
    if (w[i] == Real(0)) continue;  // pinned particles never move, so they never collide
    const Vec3<Real> xi = x.col(i), pi = p.col(i), vi = v.col(i);
    const Real r = surfaces.radius ? surfaces.radius[i] : Real(0);
    auto contact = [&](const Vec3<Real>& nrm, Real offset, const ContactMaterial<Real>& m) {
      const ContactMaterial<Real> mixed = surfaces.material ? mix_materials(m, surfaces.material[i]) : m;
      out.push_back({{i}, nrm, offset, xi, nrm.dot(vi), mixed});
    };
    for (const Plane<Real>& pl : colliders.planes) {
      // A half-space: a path that ends behind the plane crossed it (or started behind), so this is continuous.
      const Real offset = r > Real(0) ? pl.offset + r : pl.offset;
      if (pl.normal.dot(pi) < offset + margin) contact(pl.normal, offset, pl.material);
    }
    for (const Sphere<Real>& s0 : colliders.spheres) {
      const Sphere<Real> s{s0.center, r > Real(0) ? s0.radius + r : s0.radius, s0.material};  // the centre's bound
      const Real r2 = s.radius * s.radius;
      const Real t = (xi - s.center).squaredNorm() < r2 ? Real(-1) : entry_parameter(xi, Vec3<Real>(pi - xi), s);
      if (t >= Real(0)) {
        // Entered from outside: the first point where x → p enters the ball gives the tangent plane to stay above.
        const Vec3<Real> q = xi + t * (pi - xi);
        const Vec3<Real> nrm = (q - s.center).normalized();
        contact(nrm, nrm.dot(q), s.material);
      } else if ((xi - s.center).squaredNorm() < r2 || (pi - s.center).norm() < s.radius + margin) {
        // Started inside, or ends near: the tangent plane under p's direction from the centre (or x's, or +z).
        Vec3<Real> dir = pi - s.center;
        if (!(dir.squaredNorm() > tiny_squared<Real>())) dir = xi - s.center;
        if (!(dir.squaredNorm() > tiny_squared<Real>())) dir = Vec3<Real>::UnitZ();
        const Vec3<Real> nrm = dir.normalized();
        contact(nrm, nrm.dot(s.center) + s.radius, s.material);
      }
    }
  }
}

}  // namespace

template <class Real>
void generate_collisions(const Colliders<Real>& colliders, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                         const Matrix3X<Real>& v, const VectorX<Real>& w, Real margin, ParticleSurfaces<Real> surfaces,
                         std::vector<CollisionConstraint<Real>>& out) {
  collide_range(colliders, x, p, v, w, margin, surfaces, 0, Index(p.cols()), out);
}

namespace detail {

template <class Real>
void generate_collisions_chunked(const Colliders<Real>& colliders, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                                 const Matrix3X<Real>& v, const VectorX<Real>& w, Real margin,
                                 ParticleSurfaces<Real> surfaces, bool parallel, CollisionChunks<Real>& chunks,
                                 std::vector<CollisionConstraint<Real>>& out) {
  const Index n = Index(p.cols());
  constexpr Index kChunk = 1024;  // particles per chunk: enough work that a task's cost is small against it
  const Index count = (n + kChunk - 1) / kChunk;
  if (!parallel || count < 2 || tbb::this_task_arena::max_concurrency() < 2) {
    collide_range(colliders, x, p, v, w, margin, surfaces, 0, n, out);
    return;
  }
  if (chunks.size() < std::size_t(count)) chunks.resize(std::size_t(count));
  tbb::parallel_for(tbb::blocked_range<Index>(0, count, 1), [&](const tbb::blocked_range<Index>& r) {
    for (Index c = r.begin(); c < r.end(); ++c) {
      chunks[c].clear();
      collide_range(colliders, x, p, v, w, margin, surfaces, c * kChunk, std::min(n, (c + 1) * kChunk), chunks[c]);
    }
  });
  std::size_t total = out.size();
  for (Index c = 0; c < count; ++c) total += chunks[c].size();
  out.reserve(total);
  for (Index c = 0; c < count; ++c) out.insert(out.end(), chunks[c].begin(), chunks[c].end());
}

}  // namespace detail

template void generate_collisions(const Colliders<float>&, const Matrix3X<float>&, const Matrix3X<float>&,
                                  const Matrix3X<float>&, const VectorX<float>&, float, ParticleSurfaces<float>,
                                  std::vector<CollisionConstraint<float>>&);
template void generate_collisions(const Colliders<double>&, const Matrix3X<double>&, const Matrix3X<double>&,
                                  const Matrix3X<double>&, const VectorX<double>&, double, ParticleSurfaces<double>,
                                  std::vector<CollisionConstraint<double>>&);
template void detail::generate_collisions_chunked(const Colliders<float>&, const Matrix3X<float>&,
                                                  const Matrix3X<float>&, const Matrix3X<float>&, const VectorX<float>&,
                                                  float, ParticleSurfaces<float>, bool, detail::CollisionChunks<float>&,
                                                  std::vector<CollisionConstraint<float>>&);
template void detail::generate_collisions_chunked(const Colliders<double>&, const Matrix3X<double>&,
                                                  const Matrix3X<double>&, const Matrix3X<double>&,
                                                  const VectorX<double>&, double, ParticleSurfaces<double>, bool,
                                                  detail::CollisionChunks<double>&,
                                                  std::vector<CollisionConstraint<double>>&);

}  // namespace pbd
