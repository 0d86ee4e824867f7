#include "pbd/world.hpp"

#include "message.hpp"
#include "pbd/serial_solver.hpp"

#include <cmath>

namespace pbd {
namespace {

template <class Real> bool finite(const Vec3<Real>& v) { return v.allFinite(); }

// Inverse mass of a validated mass: 0 for kPinned (infinity).
template <class Real> Real inverse_mass(Real mass) { return std::isinf(mass) ? Real(0) : Real(1) / mass; }

template <class Real> void check_mass(Real mass, const std::string& what) {
  if (std::isnan(mass) || !(mass > Real(0)))
    throw Error(detail::message(what, ": mass must be > 0 (or kPinned), got ", mass));
}

void check_stiffness(const Stiffness& s, const std::string& what) {
  if (s.mode == StiffnessMode::xpbd) {
    if (!(s.compliance >= 0.0) || !std::isfinite(s.compliance))
      throw Error(detail::message(what, ": compliance must be finite and >= 0, got ", s.compliance));
  } else if (!(s.k >= 0.0 && s.k <= 1.0)) {
    throw Error(detail::message(what, ": stiffness k must be in [0, 1], got ", s.k));
  }
}

}  // namespace

template <class Real> void World<Real>::check_particle(Index i, const char* what) const {
  if (i >= num_particles())
    throw Error(detail::message(what, ": particle index ", i, " out of range (the world has ", num_particles(),
                                " particles)"));
}

template <class Real> void World<Real>::check_set(Index set, const char* what) const {
  if (set >= constraints_.sets.size())
    throw Error(detail::message(what, ": constraint set ", set, " does not exist (", constraints_.sets.size(),
                                " sets)"));
}

template <class Real> Index World<Real>::add_particle(const Vec& position, Real mass, const Vec& velocity) {
  const Index i = num_particles();
  if (!finite(position)) throw Error(detail::message("add_particle: particle ", i, ": position is not finite"));
  if (!finite(velocity)) throw Error(detail::message("add_particle: particle ", i, ": velocity is not finite"));
  check_mass(mass, detail::message("add_particle: particle ", i));
  x_.conservativeResize(3, i + 1);
  v_.conservativeResize(3, i + 1);
  w_.conservativeResize(i + 1);
  x_.col(i) = position;
  v_.col(i) = velocity;
  w_[i] = inverse_mass(mass);
  return i;
}

template <class Real> Index World<Real>::add_particles(const Positions& positions, const VectorX<Real>& masses) {
  const Index first = num_particles();
  if (positions.cols() != masses.size())
    throw Error(detail::message("add_particles: ", positions.cols(), " positions but ", masses.size(), " masses"));
  for (Eigen::Index j = 0; j < positions.cols(); ++j) {
    if (!finite<Real>(positions.col(j)))
      throw Error(detail::message("add_particles: particle ", first + j, ": position is not finite"));
    check_mass(masses[j], detail::message("add_particles: particle ", first + j));
  }
  const Eigen::Index n = first + positions.cols();
  x_.conservativeResize(3, n);
  v_.conservativeResize(3, n);
  w_.conservativeResize(n);
  x_.rightCols(positions.cols()) = positions;
  v_.rightCols(positions.cols()).setZero();
  for (Eigen::Index j = 0; j < positions.cols(); ++j) w_[first + j] = inverse_mass(masses[j]);
  return first;
}

template <class Real> void World<Real>::set_mass(Index particle, Real mass) {
  check_particle(particle, "set_mass");
  check_mass(mass, detail::message("set_mass: particle ", particle));
  w_[particle] = inverse_mass(mass);
}

template <class Real> Index World<Real>::add_constraint_set(const Stiffness& stiffness) {
  check_stiffness(stiffness, detail::message("add_constraint_set: set ", constraints_.sets.size()));
  constraints_.sets.push_back(stiffness);
  return Index(constraints_.sets.size() - 1);
}

template <class Real> Index World<Real>::add_stretch(Index a, Index b, Index set, std::optional<Real> rest) {
  const std::string what = detail::message("add_stretch: stretch constraint ", constraints_.stretch.size());
  check_particle(a, what.c_str());
  check_particle(b, what.c_str());
  check_set(set, what.c_str());
  if (a == b) throw Error(detail::message(what, ": names particle ", a, " twice"));
  const Real d = rest ? *rest : (x_.col(a) - x_.col(b)).norm();
  if (!std::isfinite(d) || d < Real(0))
    throw Error(detail::message(what, ": rest distance must be finite and >= 0, got ", d));
  constraints_.stretch.push_back({{a, b}, set, d});
  return Index(constraints_.stretch.size() - 1);
}

template <class Real> Index World<Real>::add_anchor(Index particle, Index set, std::optional<Vec> target) {
  const std::string what = detail::message("add_anchor: anchor ", constraints_.anchor.size());
  check_particle(particle, what.c_str());
  check_set(set, what.c_str());
  const Vec t = target ? *target : Vec(x_.col(particle));
  if (!finite(t)) throw Error(detail::message(what, ": target is not finite"));
  constraints_.anchor.push_back({{particle}, set, t});
  return Index(constraints_.anchor.size() - 1);
}

template <class Real> void World<Real>::add_plane(const Vec& normal, Real offset) {
  const std::string what = detail::message("add_plane: plane ", colliders_.planes.size());
  if (!finite(normal) || !std::isfinite(offset)) throw Error(what + ": normal and offset must be finite");
  const Real len = normal.norm();
  if (!(len > Real(0))) throw Error(what + ": normal has zero length");
  colliders_.planes.push_back({normal / len, offset / len});
}

template <class Real> void World<Real>::add_sphere(const Vec& center, Real radius) {
  const std::string what = detail::message("add_sphere: sphere ", colliders_.spheres.size());
  if (!finite(center)) throw Error(what + ": center is not finite");
  if (!std::isfinite(radius) || !(radius > Real(0)))
    throw Error(detail::message(what, ": radius must be finite and > 0, got ", radius));
  colliders_.spheres.push_back({center, radius});
}

template <class Real> void World<Real>::set_params(const StepParams<Real>& p) {
  if (!std::isfinite(p.dt) || !(p.dt > Real(0)))
    throw Error(detail::message("set_params: dt must be finite and > 0, got ", p.dt));
  if (p.substeps < 1) throw Error(detail::message("set_params: substeps must be >= 1, got ", p.substeps));
  if (p.iterations < 0) throw Error(detail::message("set_params: iterations must be >= 0, got ", p.iterations));
  if (!finite(p.gravity)) throw Error("set_params: gravity is not finite");
  if (!std::isfinite(p.damping) || p.damping < Real(0))
    throw Error(detail::message("set_params: damping must be finite and >= 0, got ", p.damping));
  params_ = p;
}

template <class Real> void World<Real>::step() {
  const Real h = params_.dt / Real(params_.substeps);
  coeff_.resize(constraints_.sets.size());
  for (std::size_t s = 0; s < coeff_.size(); ++s)
    coeff_[s] = coefficients<Real>(constraints_.sets[s], double(h), params_.iterations);
  for (int s = 0; s < params_.substeps; ++s) substep(h);
}

template <class Real> void World<Real>::substep(Real h) {
  const Eigen::Index n = x_.cols();
  // 1. external forces and damping (pinned particles keep v = 0)
  const Real keep = std::max(Real(0), Real(1) - params_.damping * h);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (w_[i] == Real(0)) {
      v_.col(i).setZero();
      continue;
    }
    v_.col(i) += h * params_.gravity;
    if (params_.damping > Real(0)) v_.col(i) *= keep;
  }
  // 2. predict
  p_ = x_ + h * v_;
  // 3. collisions
  collisions_.clear();
  if (!colliders_.empty()) generate_collisions(colliders_, x_, p_, w_, collisions_);
  // 4. solve
  lambda_.reset(constraints_, collisions_.size());
  for (int it = 0; it < params_.iterations; ++it)
    sweep_serial<Real>(constraints_, collisions_, coeff_, p_.data(), w_.data(), lambda_);
  // 5. update
  v_ = (p_ - x_) / h;
  x_.swap(p_);
}

template class World<float>;
template class World<double>;

}  // namespace pbd

namespace pbd {

template <class Real>
template <class Other>
World<Real>::World(const World<Other>& o)
    : x_(o.x_.template cast<Real>()), v_(o.v_.template cast<Real>()), w_(o.w_.template cast<Real>()) {
  constraints_.sets = o.constraints_.sets;
  for (const auto& c : o.constraints_.stretch) constraints_.stretch.push_back({c.particles, c.set, Real(c.rest)});
  for (const auto& c : o.constraints_.anchor)
    constraints_.anchor.push_back({c.particles, c.set, c.target.template cast<Real>()});
  for (const auto& pl : o.colliders_.planes)
    colliders_.planes.push_back({pl.normal.template cast<Real>(), Real(pl.offset)});
  for (const auto& s : o.colliders_.spheres)
    colliders_.spheres.push_back({s.center.template cast<Real>(), Real(s.radius)});
  params_ = {Real(o.params_.dt), o.params_.substeps, o.params_.iterations, o.params_.gravity.template cast<Real>(),
             Real(o.params_.damping)};
}

template World<float>::World(const World<double>&);
template World<double>::World(const World<float>&);

}  // namespace pbd
