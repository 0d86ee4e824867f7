#include "pbd/world.hpp"

#include "message.hpp"
#include "parallel_range.hpp"
#include "pbd/metrics.hpp"
#include "pbd/closed_mesh.hpp"
#include "pbd/serial_solver.hpp"

#include <chrono>
#include <cmath>

namespace pbd {
namespace {

template <class Real> bool finite(const Vec3<Real>& v) { return v.allFinite(); }

// Inverse mass of a validated mass: 0 for kPinned (infinity).
template <class Real> Real inverse_mass(Real mass) { return std::isinf(mass) ? Real(0) : Real(1) / mass; }

// Throws "<fn>: particle <index>: mass must be ..." unless mass > 0 (infinity = pinned is allowed).
template <class Real> void check_mass(Real mass, const char* fn, std::size_t index) {
  if (std::isnan(mass) || !(mass > Real(0)))
    throw Error(detail::message(fn, ": particle ", index, ": mass must be > 0 (or kPinned), got ", mass));
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

template <class Real> void World<Real>::check_particle(Index i, const char* item, std::size_t index) const {
  if (i >= num_particles())
    throw Error(detail::message(item, " ", index, ": particle index ", i, " out of range (the world has ",
                                num_particles(), " particles)"));
}

template <class Real> void World<Real>::check_set(Index set, const char* item, std::size_t index) const {
  if (set >= constraints_.sets.size())
    throw Error(detail::message(item, " ", index, ": constraint set ", set, " does not exist (",
                                constraints_.sets.size(), " sets)"));
}

template <class Real> Index World<Real>::add_particle(const Vec& position, Real mass, const Vec& velocity) {
  const Index i = num_particles();
  if (!finite(position)) throw Error(detail::message("add_particle: particle ", i, ": position is not finite"));
  if (!finite(velocity)) throw Error(detail::message("add_particle: particle ", i, ": velocity is not finite"));
  check_mass(mass, "add_particle", i);
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
    check_mass(masses[j], "add_particles", first + j);
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

template <class Real>
Index World<Real>::add_particles_by_inverse_mass(const Positions& positions, const VectorX<Real>& inverse_masses) {
  const Index first = num_particles();
  if (positions.cols() != inverse_masses.size())
    throw Error(detail::message("add_particles_by_inverse_mass: ", positions.cols(), " positions but ",
                                inverse_masses.size(), " inverse masses"));
  for (Eigen::Index j = 0; j < positions.cols(); ++j) {
    if (!finite<Real>(positions.col(j)))
      throw Error(detail::message("add_particles_by_inverse_mass: particle ", first + j, ": position is not finite"));
    if (!std::isfinite(inverse_masses[j]) || !(inverse_masses[j] >= Real(0)))
      throw Error(detail::message("add_particles_by_inverse_mass: particle ", first + j,
                                  ": inverse mass must be finite and >= 0 (0 = pinned), got ", inverse_masses[j]));
  }
  const Eigen::Index n = first + positions.cols();
  x_.conservativeResize(3, n);
  v_.conservativeResize(3, n);
  w_.conservativeResize(n);
  x_.rightCols(positions.cols()) = positions;
  v_.rightCols(positions.cols()).setZero();
  w_.tail(positions.cols()) = inverse_masses;
  return first;
}

template <class Real> void World<Real>::set_mass(Index particle, Real mass) {
  check_particle(particle, "set_mass: particle", particle);
  check_mass(mass, "set_mass", particle);
  if ((w_[particle] == Real(0)) != (inverse_mass(mass) == Real(0))) colored_.invalidate();  // pins changed
  w_[particle] = inverse_mass(mass);
}

template <class Real> Index World<Real>::add_constraint_set(const Stiffness& stiffness) {
  check_stiffness(stiffness, detail::message("add_constraint_set: set ", constraints_.sets.size()));
  constraints_.sets.push_back(stiffness);
  return Index(constraints_.sets.size() - 1);
}

template <class Real> Index World<Real>::add_stretch(Index a, Index b, Index set, std::optional<Real> rest) {
  // Messages are built only when something is wrong: adding must stay cheap for millions of constraints.
  const char* item = "add_stretch: stretch constraint";
  const std::size_t index = constraints_.stretch.size();
  auto what = [&] { return detail::message(item, " ", index); };
  check_particle(a, item, index);
  check_particle(b, item, index);
  check_set(set, item, index);
  if (a == b) throw Error(detail::message(what(), ": names particle ", a, " twice"));
  const Real d = rest ? *rest : (x_.col(a) - x_.col(b)).norm();
  if (!std::isfinite(d) || d < Real(0))
    throw Error(detail::message(what(), ": rest distance must be finite and >= 0, got ", d));
  constraints_.stretch.push_back({{a, b}, set, d});
  return Index(constraints_.stretch.size() - 1);
}

template <class Real> Index World<Real>::add_anchor(Index particle, Index set, std::optional<Vec> target) {
  const char* item = "add_anchor: anchor";
  const std::size_t index = constraints_.anchor.size();
  auto what = [&] { return detail::message(item, " ", index); };
  check_particle(particle, item, index);
  check_set(set, item, index);
  const Vec t = target ? *target : Vec(x_.col(particle));
  if (!finite(t)) throw Error(detail::message(what(), ": target is not finite"));
  constraints_.anchor.push_back({{particle}, set, t});
  return Index(constraints_.anchor.size() - 1);
}

template <class Real>
Index World<Real>::add_bending(Index p1, Index p2, Index p3, Index p4, Index set, std::optional<Real> rest) {
  const char* item = "add_bending: bending constraint";
  const std::size_t index = constraints_.bending.size();
  auto what = [&] { return detail::message(item, " ", index); };
  const std::array<Index, 4> ids{p1, p2, p3, p4};
  for (Index i : ids) check_particle(i, item, index);
  check_set(set, item, index);
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      if (ids[a] == ids[b]) throw Error(detail::message(what(), ": names particle ", ids[a], " twice"));
  Real phi;
  if (rest) {
    phi = *rest;
  } else {
    phi = dihedral_angle<Real>(x_.col(p1), x_.col(p2), x_.col(p3), x_.col(p4));
    if (phi < Real(0))
      throw Error(detail::message(what(), ": a triangle is degenerate, so the rest angle is undefined (give it)"));
  }
  if (!(phi >= Real(0) && phi <= Real(3.14159265358979323846)))
    throw Error(detail::message(what(), ": rest angle must be in [0, pi], got ", phi));
  constraints_.bending.push_back({ids, set, phi});
  return Index(index);
}

template <class Real> Index World<Real>::add_area(Index a, Index b, Index c, Index set, std::optional<Real> rest) {
  const char* item = "add_area: area constraint";
  const std::size_t index = constraints_.area.size();
  auto what = [&] { return detail::message(item, " ", index); };
  for (Index i : {a, b, c}) check_particle(i, item, index);
  check_set(set, item, index);
  if (a == b || b == c || a == c) throw Error(detail::message(what(), ": names a particle twice"));
  const Real area = rest ? *rest : triangle_area<Real>(x_.col(a), x_.col(b), x_.col(c));
  if (!std::isfinite(area) || area < Real(0))
    throw Error(detail::message(what(), ": rest area must be finite and >= 0, got ", area));
  constraints_.area.push_back({{a, b, c}, set, area});
  return Index(index);
}

template <class Real>
Index World<Real>::add_volume(std::span<const std::array<Index, 3>> triangles, Index set,
                              const PressureSchedule& pressure, std::optional<Real> rest) {
  const char* item = "add_volume: volume constraint";
  const std::size_t index = constraints_.volume.size();
  auto what = [&] { return detail::message(item, " ", index); };
  check_set(set, item, index);
  if (const auto defect = closed_mesh_defect(triangles, num_particles())) throw Error(what() + ": " + *defect);
  if (!std::isfinite(pressure.from) || !std::isfinite(pressure.to) || !(pressure.from > 0.0) ||
      !(pressure.to > 0.0) || !std::isfinite(pressure.duration) || pressure.duration < 0.0)
    throw Error(what() + ": pressure from/to must be finite and > 0, duration finite and >= 0");
  // Flat or inside-out: the enclosed volume must be clearly positive against the mesh's extent (scale-free).
  Vec lo = x_.col(triangles[0][0]), hi = lo;
  for (const auto& t : triangles)
    for (Index i : t) {
      lo = lo.cwiseMin(Vec(x_.col(i)));
      hi = hi.cwiseMax(Vec(x_.col(i)));
    }
  const Real extent = (hi - lo).norm();
  const Real six_v = six_volume<Real>(triangles, x_);
  if (!rest) {
    if (six_v < Real(0))
      throw Error(detail::message(what(), ": the mesh encloses a negative volume (", six_v / Real(6),
                                  "): it is inside out; its triangles must wind counter-clockwise seen from outside"));
    if (!(six_v > Real(6) * parallel_sine<Real>() * extent * extent * extent))
      throw Error(detail::message(what(), ": the mesh is flat (volume ", six_v / Real(6), " for an extent of ",
                                  extent, "): it encloses nothing to keep"));
  }
  const Real r = rest ? *rest : six_v;
  if (!std::isfinite(r) || !(r > Real(0)))
    throw Error(detail::message(what(), ": rest volume must be finite and > 0, got ", r));
  constraints_.volume.add(triangles, set, r, pressure);
  return Index(index);
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
  if (!std::isfinite(p.collision_margin) || p.collision_margin < Real(0))
    throw Error(detail::message("set_params: collision_margin must be finite and >= 0, got ", p.collision_margin));
  if (!(p.jacobi_omega > Real(0) && p.jacobi_omega < Real(2)))
    throw Error(detail::message("set_params: jacobi_omega must be in (0, 2), got ", p.jacobi_omega));
  if (name(p.solver) == "?") throw Error("set_params: unknown solver");
  params_ = p;
}

template <class Real> void World<Real>::set_time(double seconds) {
  if (!std::isfinite(seconds)) throw Error(detail::message("set_time: time must be finite, got ", seconds));
  time_ = seconds;
}

template <class Real> void World<Real>::step() { advance(nullptr); }

template <class Real> void World<Real>::step(Eigen::Ref<const Positions> forces) {
  if (forces.rows() != 3 || forces.cols() != x_.cols())
    throw Error(detail::message("step: forces must be 3 x ", x_.cols(), ", got ", forces.rows(), " x ", forces.cols()));
  for (Eigen::Index i = 0; i < forces.cols(); ++i)
    if (!forces.col(i).allFinite()) throw Error(detail::message("step: force on particle ", i, " is not finite"));
  if (forces.outerStride() == 3) return advance(forces.data());
  const Positions copy = forces;  // a strided view: make it contiguous once
  advance(copy.data());
}

template <class Real> void World<Real>::advance(const Real* forces) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  stats_ = StepStats{};
  const Real h = params_.dt / Real(params_.substeps);
  coeff_.resize(constraints_.sets.size());
  for (std::size_t s = 0; s < coeff_.size(); ++s)
    coeff_[s] = coefficients<Real>(constraints_.sets[s], double(h), params_.iterations);
  if (params_.solver != Solver::serial) {
    const auto c0 = clock::now();
    ensure_colored();
    stats_.seconds_coloring = std::chrono::duration<double>(clock::now() - c0).count();
    stats_.colors = colored_.num_colors(custom_);
  }
  // A force callback may fail at a later sub-step: keep the state it started from so nothing is half-stepped.
  const bool rollback = force_callback_ && params_.substeps > 1;
  if (rollback) {
    rollback_x_ = x_;
    rollback_v_ = v_;
  }
  try {
    for (int s = 0; s < params_.substeps; ++s) {
      const double t = time_ + double(h) * double(s + 1);
      const Real* f = forces;
      if (force_callback_) {
        callback_forces_.setZero(3, x_.cols());
        force_callback_(t, x_, callback_forces_);
        for (Eigen::Index i = 0; i < callback_forces_.cols(); ++i)
          if (!callback_forces_.col(i).allFinite())
            throw Error(detail::message("step: the force callback returned a non-finite force on particle ", i,
                                        " at sub-step ", s, " (t = ", t, " s); the step was not taken"));
        if (forces) callback_forces_ += Eigen::Map<const Positions>(forces, 3, x_.cols());
        f = callback_forces_.data();
      }
      substep(h, t, f);
    }
  } catch (...) {
    if (rollback) {
      x_ = rollback_x_;  // copied back, not swapped: maps the host holds on positions() stay valid
      v_ = rollback_v_;
    }
    throw;
  }
  time_ += double(params_.dt);
  stats_.substeps = params_.substeps;
  stats_.sweeps = params_.substeps * params_.iterations;
  stats_.collisions = collisions_.size();
  if (measure_violation_) measure_violation();
  stats_.seconds = std::chrono::duration<double>(clock::now() - t0).count();
}

template <class Real> void World<Real>::set_coloring(const coloring::Options& options) {
  coloring_ = options;
  colored_.invalidate();
}

template <class Real> void World<Real>::ensure_colored() {
  if (!colored_.built()) colored_.build(constraints_, w_, coloring_, custom_);
  else if (!colored_.up_to_date(constraints_, custom_, num_particles())) colored_.update(constraints_, w_, coloring_, custom_);
}

template <class Real> const ColoredConstraints<Real>& World<Real>::colored_constraints() {
  ensure_colored();
  return colored_.constraints();
}

template <class Real> void World<Real>::substep(Real h, double time, const Real* f) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const Solver solver = params_.solver;
  const bool parallel = solver == Solver::colored || solver == Solver::jacobi;
  const Index n = num_particles();
  Real* x = x_.data();
  Real* v = v_.data();
  const Real* w = w_.data();
  p_.resize(3, n);
  Real* p = p_.data();
  // 1.-2. external forces, damping, predict (per particle, so any cut of the range gives the same bits)
  const Real keep = std::max(Real(0), Real(1) - params_.damping * h);
  const bool damp = params_.damping > Real(0);
  const Vec g = params_.gravity;
  detail::run_range(0, n, parallel, parallel_, particle_partitioners_[0], [&](Index b, Index e) {
    for (Index i = b; i < e; ++i) {
      Real* vi = v + 3 * std::size_t(i);
      const Real* xi = x + 3 * std::size_t(i);
      for (int d = 0; d < 3; ++d) {
        if (w[i] == Real(0)) vi[d] = Real(0);  // pinned particles keep v = 0
        else {
          vi[d] += h * g[d];
          if (f) vi[d] += h * (w[i] * f[3 * std::size_t(i) + d]);  // external force: a = w·f
          if (damp) vi[d] *= keep;
        }
        p[3 * std::size_t(i) + d] = xi[d] + h * vi[d];
      }
    }
  });
  const auto t1 = clock::now();
  // 3. collisions
  collisions_.clear();
  if (!colliders_.empty()) generate_collisions(colliders_, x_, p_, w_, params_.collision_margin, collisions_);
  const auto t2 = clock::now();
  // 4. solve
  if (solver == Solver::serial) {
    lambda_.reset(constraints_, collisions_.size());
    for (const auto& t : custom_.types()) t->reset_lambda();
    volume_scratch_.set_targets(constraints_.volume, time);
    for (int it = 0; it < params_.iterations; ++it)
      sweep_serial<Real>(constraints_, collisions_, coeff_, p, w, lambda_, &volume_scratch_, &custom_);
  } else {
    colored_.begin_substep(collisions_, time, custom_);
    for (int it = 0; it < params_.iterations; ++it) {
      if (solver == Solver::jacobi)
        colored_.sweep_jacobi(collisions_, coeff_, p, w, params_.jacobi_omega, parallel, parallel_, custom_);
      else
        colored_.sweep_gauss_seidel(collisions_, coeff_, p, w, parallel, parallel_, custom_);
    }
    colored_.end_substep(p, parallel, parallel_);
  }
  const auto t3 = clock::now();
  // 5. update: v = (p − x)/h, x = p
  detail::run_range(0, n, parallel, parallel_, particle_partitioners_[1], [&](Index b, Index e) {
    for (std::size_t k = 3 * std::size_t(b); k < 3 * std::size_t(e); ++k) v[k] = (p[k] - x[k]) / h;
  });
  x_.swap(p_);
  const auto t4 = clock::now();
  using seconds = std::chrono::duration<double>;
  stats_.seconds_integrate += seconds(t1 - t0).count() + seconds(t4 - t3).count();
  stats_.seconds_collisions += seconds(t2 - t1).count();
  stats_.seconds_solve += seconds(t3 - t2).count();
}

template <class Real> void World<Real>::measure_violation() {
  // The same normalized measures as the study's (metrics.hpp), so both report one definition of "violation".
  for (const NamedViolation& v : constraint_violations(*this))
    stats_.violation.push_back({v.type, v.value.count, v.value.rms, v.value.max});
}

template <class Real>
template <class C>
void World<Real>::erase(std::vector<C>& items, ColoredArray<C>& colored, std::span<const Index> indices,
                        const char* what) {
  std::vector<std::uint8_t> drop(items.size(), 0);
  for (Index i : indices) {
    if (i >= items.size())
      throw Error(detail::message(what, ": constraint index ", i, " out of range (", items.size(), " constraints)"));
    if (drop[i]) throw Error(detail::message(what, ": constraint index ", i, " given twice"));
    drop[i] = 1;
  }
  const bool colored_matches = colored_.built() && colored.color.size() == items.size();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < items.size(); ++i)
    if (!drop[i]) {
      items[kept] = items[i];
      if (colored_matches) colored.color[kept] = colored.color[i];
      ++kept;
    }
  items.resize(kept);
  if (colored_matches) {  // the others keep their colors: lay the array out again, color nothing
    colored.color.resize(kept);
    layout_by_color(colored, items);
    colored_.count_static(custom_);
  } else {
    colored_.invalidate();
  }
}

template <class Real> void World<Real>::remove_stretch(std::span<const Index> indices) {
  erase(constraints_.stretch, colored_.colored_.stretch, indices, "remove_stretch");
}
template <class Real> void World<Real>::remove_anchor(std::span<const Index> indices) {
  erase(constraints_.anchor, colored_.colored_.anchor, indices, "remove_anchor");
}
template <class Real> void World<Real>::remove_bending(std::span<const Index> indices) {
  erase(constraints_.bending, colored_.colored_.bending, indices, "remove_bending");
}
template <class Real> void World<Real>::remove_area(std::span<const Index> indices) {
  erase(constraints_.area, colored_.colored_.area, indices, "remove_area");
}

template <class Real> void World<Real>::remove_particle(Index particle) {
  check_particle(particle, "remove_particle: particle", particle);
  for (Index p : constraints_.volume.particles)
    if (p == particle)
      throw Error(detail::message("remove_particle: particle ", particle,
                                  " belongs to a volume constraint; volume meshes cannot lose particles"));
  auto touching = [&](const auto& items) {
    std::vector<Index> out;
    for (std::size_t i = 0; i < items.size(); ++i)
      for (Index p : items[i].particles)
        if (p == particle) {
          out.push_back(Index(i));
          break;
        }
    return out;
  };
  remove_stretch(touching(constraints_.stretch));
  remove_anchor(touching(constraints_.anchor));
  remove_bending(touching(constraints_.bending));
  remove_area(touching(constraints_.area));
  for (const auto& t : custom_.types()) t->erase_touching(particle);
  w_[particle] = Real(0);  // pinned: never moves, never collides
  v_.col(particle).setZero();
  colored_.invalidate();   // a particle became pinned: conflicts changed
}

template class World<float>;
template class World<double>;

}  // namespace pbd
