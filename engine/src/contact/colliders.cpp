#include "pbd/colliders.hpp"

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

}  // namespace

template <class Real>
void generate_collisions(const Colliders<Real>& colliders, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                         const Matrix3X<Real>& v, const VectorX<Real>& w, Real margin, ParticleSurfaces<Real> surfaces,
                         std::vector<CollisionConstraint<Real>>& out) {
  const Index n = Index(p.cols());
  for (Index i = 0; i < n; ++i) {
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

template void generate_collisions(const Colliders<float>&, const Matrix3X<float>&, const Matrix3X<float>&,
                                  const Matrix3X<float>&, const VectorX<float>&, float, ParticleSurfaces<float>,
                                  std::vector<CollisionConstraint<float>>&);
template void generate_collisions(const Colliders<double>&, const Matrix3X<double>&, const Matrix3X<double>&,
                                  const Matrix3X<double>&, const VectorX<double>&, double, ParticleSurfaces<double>,
                                  std::vector<CollisionConstraint<double>>&);

}  // namespace pbd
