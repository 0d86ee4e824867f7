// The engine's exported input checks (pbd/checks.hpp): World and pbd::io's DescriptionBuilder both call them.
#include "pbd/checks.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/solver.hpp"
#include "pbd/step_limits.hpp"

#include <limits>

namespace pbd {

template <class Real> void check_mass(Real mass, const char* fn, std::size_t index) {
  if (std::isnan(mass) || !(mass > Real(0)))
    throw Error(detail::message(fn, ": particle ", index, ": mass must be > 0 (or kPinned), got ", mass));
  // The world keeps 1 / mass: where Real cannot hold it as a normal number, a huge mass would be pinned without a
  // word (its inverse rounds to 0) or lose its motion, and a tiny one get an infinite inverse.
  const Real inverse = Real(1) / mass;
  if (!std::isinf(mass) && !(inverse >= std::numeric_limits<Real>::min() && inverse <= std::numeric_limits<Real>::max()))
    throw Error(detail::message(fn, ": particle ", index, ": mass ", mass, " kg is out of range for ",
                                sizeof(Real) == 4 ? "float" : "double", ": its inverse ", inverse,
                                " is not a normal number (the mass must be in [", Real(1) / std::numeric_limits<Real>::max(),
                                ", ", Real(1) / std::numeric_limits<Real>::min(), "], or kPinned)"));
}

template <class Real>
void check_particles(const Matrix3X<Real>& positions, const VectorX<Real>& masses, const char* fn, Index first) {
  if (positions.cols() != masses.size())
    throw Error(detail::message(fn, ": ", positions.cols(), " positions but ", masses.size(), " masses"));
  for (Eigen::Index j = 0; j < positions.cols(); ++j) {
    if (!positions.col(j).allFinite())
      throw Error(detail::message(fn, ": particle ", first + j, ": position is not finite"));
    check_mass(masses[j], fn, first + j);
  }
}

std::string Material::error() const {
  const auto bad = [](const char* name, double v, const char* rule) { return detail::message(name, " must be ", rule, ", got ", v); };
  if (!(stiffness > 0.0) || !std::isfinite(stiffness)) return bad("stiffness", stiffness, "finite and > 0 (N per unit strain)");
  if (!(toe_strain >= 0.0) || !std::isfinite(toe_strain)) return bad("toe_strain", toe_strain, "finite and >= 0");
  if (!(yield_strain >= toe_strain)) return bad("yield_strain", yield_strain, "at least toe_strain (the yield is on the linear part)");
  if (!(hardening >= 0.0) || !std::isfinite(hardening)) return bad("hardening", hardening, "finite and >= 0 (N per unit plastic strain)");
  if (!(rupture_strain > 0.0)) return bad("rupture_strain", rupture_strain, "> 0");
  return {};
}

void check_surface(std::span<const std::array<Index, 3>> triangles, std::span<const std::array<Index, 2>> cut,
                   std::size_t n, const char* fn) {
  auto check = [&](const auto& items, const char* item) {
    for (std::size_t k = 0; k < items.size(); ++k)
      for (std::size_t i = 0; i < items[k].size(); ++i) {
        if (items[k][i] >= n)
          throw Error(detail::message(fn, ": ", item, " ", k, ": particle index ", items[k][i], " out of range (", n,
                                      " particles)"));
        for (std::size_t j = 0; j < i; ++j)
          if (items[k][i] == items[k][j])
            throw Error(detail::message(fn, ": ", item, " ", k, ": names particle ", items[k][i], " twice"));
      }
  };
  check(triangles, "triangle");
  check(cut, "cut edge");
}

void check_stiffness(const Stiffness& s, const std::string& what) {
  if (s.mode == StiffnessMode::material) {
    if (const std::string why = s.material.error(); !why.empty()) throw Error(detail::message(what, ": ", why));
  } else if (s.mode == StiffnessMode::xpbd) {
    if (!(s.compliance >= 0.0) || !std::isfinite(s.compliance))
      throw Error(detail::message(what, ": compliance must be finite and >= 0, got ", s.compliance));
  } else if (!(s.k >= 0.0 && s.k <= 1.0)) {
    throw Error(detail::message(what, ": stiffness k must be in [0, 1], got ", s.k));
  }
}

template <class Real> void check_params(const StepParams<Real>& p) {
  if (!std::isfinite(p.dt) || !(p.dt > Real(0)))
    throw Error(detail::message("set_params: dt must be finite and > 0, got ", p.dt));
  if (p.substeps < 1 || p.substeps > kMaxSubsteps)
    throw Error(detail::message("set_params: substeps must be in [1, ", kMaxSubsteps, "], got ", p.substeps));
  if (p.iterations < 0 || p.iterations > kMaxIterations)
    throw Error(detail::message("set_params: iterations must be in [0, ", kMaxIterations, "], got ", p.iterations));
  if (sweeps_per_step(p.substeps, p.iterations) > kMaxSweepsPerStep)
    throw Error(detail::message("set_params: substeps × iterations is ", sweeps_per_step(p.substeps, p.iterations),
                                " sweeps a step, more than the limit of ", kMaxSweepsPerStep,
                                " (pbd/step_limits.hpp: far more than any step needs to converge)"));
  if (!p.gravity.allFinite()) throw Error("set_params: gravity is not finite");
  if (!std::isfinite(p.damping) || p.damping < Real(0))
    throw Error(detail::message("set_params: damping must be finite and >= 0, got ", p.damping));
  if (!std::isfinite(p.collision_margin) || p.collision_margin < Real(0) || double(p.collision_margin) > kMaxContactLength)
    throw Error(detail::message("set_params: collision_margin must be finite and >= 0 and at most ", kMaxContactLength,
                                " m, got ", p.collision_margin));
  if (!(p.jacobi_omega > Real(0) && p.jacobi_omega < Real(2)))
    throw Error(detail::message("set_params: jacobi_omega must be in (0, 2), got ", p.jacobi_omega));
  if (name(p.solver) == "?") throw Error("set_params: unknown solver");
  if (p.chebyshev.enabled) {
    const auto& c = p.chebyshev;
    if (p.solver == Solver::serial)
      throw Error("set_params: chebyshev: the serial reference solver is never accelerated (use serial-colored)");
    if (!(c.rho >= Real(0) && c.rho < Real(1)))
      throw Error(detail::message("set_params: chebyshev.rho must be in [0, 1) (0: estimated), got ", c.rho));
    if (!(c.max_rho > Real(0) && c.max_rho < Real(1)))
      throw Error(detail::message("set_params: chebyshev.max_rho must be in (0, 1), got ", c.max_rho));
    if (c.delay < 1) throw Error(detail::message("set_params: chebyshev.delay must be >= 1, got ", c.delay));
    if (c.rho == Real(0) && p.iterations < 4)
      throw Error(detail::message("set_params: chebyshev: estimating rho needs iterations >= 4, got ", p.iterations));
    if (!(c.diverge > Real(1)) || !std::isfinite(c.diverge))
      throw Error(detail::message("set_params: chebyshev.diverge must be finite and > 1, got ", c.diverge));
  }
  check_hierarchy(p.hierarchy);
}

void check_hierarchy(const Hierarchy& h) {
  if (h.levels < 1 || h.levels > 16)
    throw Error(detail::message("set_params: hierarchy.levels must be in [1, 16], got ", h.levels));
  if (h.parents < 1 || h.parents > 8)
    throw Error(detail::message("set_params: hierarchy.parents must be in [1, 8], got ", h.parents));
  if (h.sweeps < 1 || h.sweeps > 64)
    throw Error(detail::message("set_params: hierarchy.sweeps must be in [1, 64], got ", h.sweeps));
  if (!(h.slack >= 0.0 && h.slack <= 0.1))
    throw Error(detail::message("set_params: hierarchy.slack must be in [0, 0.1], got ", h.slack));
}

template <class Real>
Real check_plane(const Vec3<Real>& normal, Real offset, const ContactMaterial<Real>& material, const std::string& what) {
  if (!normal.allFinite() || !std::isfinite(offset)) throw Error(what + ": normal and offset must be finite");
  const Real len = normal.norm();
  if (!(len > Real(0))) throw Error(what + ": normal has zero length");
  if (!(std::abs(offset / len) <= max_collider_length<Real>()))
    throw Error(detail::message(what, ": offset must be at most ", max_collider_length<Real>(),
                                " m from the origin (a contact's arithmetic squares it), got ", offset / len));
  check_contact_material(material, what);
  return len;
}

template <class Real>
void check_sphere(const Vec3<Real>& center, Real radius, const ContactMaterial<Real>& material, const std::string& what) {
  if (!center.allFinite()) throw Error(what + ": center is not finite");
  if (!(center.cwiseAbs().maxCoeff() <= max_collider_length<Real>()))
    throw Error(detail::message(what, ": center must be at most ", max_collider_length<Real>(),
                                " m from the origin along each axis (a contact's arithmetic squares it)"));
  if (!std::isfinite(radius) || !(radius > Real(0)) || !(radius <= max_collider_length<Real>()))
    throw Error(detail::message(what, ": radius must be finite and > 0 and at most ", max_collider_length<Real>(),
                                " m (a contact's arithmetic squares it), got ", radius));
  check_contact_material(material, what);
}

namespace detail {

std::string constraint_item(const char* name, const char* noun, std::size_t index) {
  return message("add_", name, ": ", noun, " ", index);
}

void fail_particle_index(const std::string& item, Index i, std::size_t n) {
  throw Error(message(item, ": particle index ", i, " out of range (the world has ", n, " particles)"));
}

void fail_set_index(const std::string& item, Index set, std::size_t n) {
  throw Error(message(item, ": constraint set ", set, " does not exist (", n, " sets)"));
}

void fail_constraint(const std::string& item, const std::string& what) { throw Error(item + ": " + what); }

}  // namespace detail

#define PBD_CHECKS_INSTANTIATE(Real)                                                                         \
  template void check_mass(Real, const char*, std::size_t);                                                  \
  template void check_particles(const Matrix3X<Real>&, const VectorX<Real>&, const char*, Index);          \
  template void check_params(const StepParams<Real>&);                                                       \
  template Real check_plane(const Vec3<Real>&, Real, const ContactMaterial<Real>&, const std::string&);     \
  template void check_sphere(const Vec3<Real>&, Real, const ContactMaterial<Real>&, const std::string&);
PBD_CHECKS_INSTANTIATE(float)
PBD_CHECKS_INSTANTIATE(double)
#undef PBD_CHECKS_INSTANTIATE

}  // namespace pbd
