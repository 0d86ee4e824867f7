#include "pbd/io/description_builder.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/closed_mesh.hpp"
#include "pbd/constraints/area.hpp"
#include "pbd/constraints/bending.hpp"
#include "pbd/constraints/degenerate.hpp"
#include "pbd/solver.hpp"

#include <cmath>
#include <cstdint>
#include <string>

// Every check, message and expression below is World<double>'s (engine/src/world.cpp), applied to the description's
// arrays instead of a world's: keep the two in step (tests/io/description_builder_test.cpp compares them).
namespace pbd {
namespace {

bool finite(const Vec3<double>& v) { return v.allFinite(); }

// Inverse mass of a validated mass: 0 for kPinned (infinity).
double inverse_mass(double mass) { return std::isinf(mass) ? 0.0 : 1.0 / mass; }

// Throws "<fn>: particle <index>: mass must be ..." unless mass > 0 (infinity = pinned is allowed).
void check_mass(double mass, const char* fn, std::size_t index) {
  if (std::isnan(mass) || !(mass > 0.0))
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

void DescriptionBuilder::check_particle(Index i, const char* item, std::size_t index) const {
  if (i >= num_particles())
    throw Error(detail::message(item, " ", index, ": particle index ", i, " out of range (the world has ",
                                num_particles(), " particles)"));
}

void DescriptionBuilder::check_set(Index set, const char* item, std::size_t index) const {
  if (set >= d_.sets.size())
    throw Error(detail::message(item, " ", index, ": constraint set ", set, " does not exist (", d_.sets.size(),
                                " sets)"));
}

Index DescriptionBuilder::add_particles(const Positions& positions, const VectorX<double>& masses) {
  const Index first = num_particles();
  if (positions.cols() != masses.size())
    throw Error(detail::message("add_particles: ", positions.cols(), " positions but ", masses.size(), " masses"));
  for (Eigen::Index j = 0; j < positions.cols(); ++j) {
    if (!finite(positions.col(j)))
      throw Error(detail::message("add_particles: particle ", first + j, ": position is not finite"));
    check_mass(masses[j], "add_particles", first + j);
  }
  const Eigen::Index n = first + positions.cols();
  d_.positions.conservativeResize(3, n);
  d_.velocities.conservativeResize(3, n);
  d_.inverse_masses.conservativeResize(n);
  d_.positions.rightCols(positions.cols()) = positions;
  d_.velocities.rightCols(positions.cols()).setZero();
  for (Eigen::Index j = 0; j < positions.cols(); ++j) d_.inverse_masses[first + j] = inverse_mass(masses[j]);
  return first;
}

Index DescriptionBuilder::add_constraint_set(const Stiffness& stiffness) {
  check_stiffness(stiffness, detail::message("add_constraint_set: set ", d_.sets.size()));
  d_.sets.push_back(stiffness);
  return Index(d_.sets.size() - 1);
}

Index DescriptionBuilder::add_stretch(Index a, Index b, Index set, std::optional<double> rest) {
  const char* item = "add_stretch: stretch constraint";
  const std::size_t index = d_.stretch.size();
  auto what = [&] { return detail::message(item, " ", index); };
  check_particle(a, item, index);
  check_particle(b, item, index);
  check_set(set, item, index);
  if (a == b) throw Error(detail::message(what(), ": names particle ", a, " twice"));
  const Positions& x = d_.positions;
  const double d = rest ? *rest : (x.col(a) - x.col(b)).norm();
  if (!std::isfinite(d) || d < 0.0)
    throw Error(detail::message(what(), ": rest distance must be finite and >= 0, got ", d));
  d_.stretch.push_back({{a, b}, set, d});
  return Index(index);
}

Index DescriptionBuilder::add_anchor(Index particle, Index set, std::optional<Vec> target) {
  const char* item = "add_anchor: anchor";
  const std::size_t index = d_.anchors.size();
  auto what = [&] { return detail::message(item, " ", index); };
  check_particle(particle, item, index);
  check_set(set, item, index);
  const Vec t = target ? *target : Vec(d_.positions.col(particle));
  if (!finite(t)) throw Error(detail::message(what(), ": target is not finite"));
  d_.anchors.push_back({particle, set, t});
  return Index(index);
}

Index DescriptionBuilder::add_bending(Index p1, Index p2, Index p3, Index p4, Index set, std::optional<double> rest) {
  const char* item = "add_bending: bending constraint";
  const std::size_t index = d_.bending.size();
  auto what = [&] { return detail::message(item, " ", index); };
  const std::array<Index, 4> ids{p1, p2, p3, p4};
  for (Index i : ids) check_particle(i, item, index);
  check_set(set, item, index);
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      if (ids[a] == ids[b]) throw Error(detail::message(what(), ": names particle ", ids[a], " twice"));
  const Positions& x = d_.positions;
  double phi;
  if (rest) {
    phi = *rest;
  } else {
    phi = dihedral_angle<double>(x.col(p1), x.col(p2), x.col(p3), x.col(p4));
    if (phi < 0.0)
      throw Error(detail::message(what(), ": a triangle is degenerate, so the rest angle is undefined (give it)"));
  }
  if (!(phi >= 0.0 && phi <= double(3.14159265358979323846f)))  // World's bound: π rounded to float
    throw Error(detail::message(what(), ": rest angle must be in [0, pi], got ", phi));
  d_.bending.push_back({ids, set, phi});
  return Index(index);
}

Index DescriptionBuilder::add_area(Index a, Index b, Index c, Index set, std::optional<double> rest) {
  const char* item = "add_area: area constraint";
  const std::size_t index = d_.area.size();
  auto what = [&] { return detail::message(item, " ", index); };
  for (Index i : {a, b, c}) check_particle(i, item, index);
  check_set(set, item, index);
  if (a == b || b == c || a == c) throw Error(detail::message(what(), ": names a particle twice"));
  const Positions& x = d_.positions;
  const double area = rest ? *rest : triangle_area<double>(x.col(a), x.col(b), x.col(c));
  if (!std::isfinite(area) || area < 0.0)
    throw Error(detail::message(what(), ": rest area must be finite and >= 0, got ", area));
  d_.area.push_back({{a, b, c}, set, area});
  return Index(index);
}

Index DescriptionBuilder::add_volume(std::span<const std::array<Index, 3>> triangles, Index set,
                                     const PressureSchedule& pressure, std::optional<double> rest) {
  const char* item = "add_volume: volume constraint";
  const std::size_t index = d_.volumes.size();
  auto what = [&] { return detail::message(item, " ", index); };
  check_set(set, item, index);
  const double r = checked_rest_volume<double>(triangles, d_.positions, pressure, rest, what());
  d_.volumes.push_back({{triangles.begin(), triangles.end()}, set, r, pressure});
  return Index(index);
}

void DescriptionBuilder::add_plane(const Vec& normal, double offset, const ContactMaterial<double>& material) {
  const std::string what = detail::message("add_plane: plane ", d_.planes.size());
  if (!finite(normal) || !std::isfinite(offset)) throw Error(what + ": normal and offset must be finite");
  const double len = normal.norm();
  if (!(len > 0.0)) throw Error(what + ": normal has zero length");
  check_contact_material(material, what);
  d_.planes.push_back({normal / len, offset / len, material});
}

void DescriptionBuilder::add_sphere(const Vec& center, double radius, const ContactMaterial<double>& material) {
  const std::string what = detail::message("add_sphere: sphere ", d_.spheres.size());
  if (!finite(center)) throw Error(what + ": center is not finite");
  if (!std::isfinite(radius) || !(radius > 0.0))
    throw Error(detail::message(what, ": radius must be finite and > 0, got ", radius));
  check_contact_material(material, what);
  d_.spheres.push_back({center, radius, material});
}

Index DescriptionBuilder::add_contact_body(const ContactBody<double>& body) {
  auto& bodies = d_.contact_bodies;
  const std::string what = detail::message("add_contact_body: body ", bodies.size());
  check_contact_body<double>(body, num_particles(), bodies, what);
  bodies.push_back(body);
  return Index(bodies.size() - 1);
}

void DescriptionBuilder::set_params(const StepParams<double>& p) {
  if (!std::isfinite(p.dt) || !(p.dt > 0.0))
    throw Error(detail::message("set_params: dt must be finite and > 0, got ", p.dt));
  if (p.substeps < 1) throw Error(detail::message("set_params: substeps must be >= 1, got ", p.substeps));
  if (p.iterations < 0) throw Error(detail::message("set_params: iterations must be >= 0, got ", p.iterations));
  if (!finite(p.gravity)) throw Error("set_params: gravity is not finite");
  if (!std::isfinite(p.damping) || p.damping < 0.0)
    throw Error(detail::message("set_params: damping must be finite and >= 0, got ", p.damping));
  if (!std::isfinite(p.collision_margin) || p.collision_margin < 0.0)
    throw Error(detail::message("set_params: collision_margin must be finite and >= 0, got ", p.collision_margin));
  if (!(p.jacobi_omega > 0.0 && p.jacobi_omega < 2.0))
    throw Error(detail::message("set_params: jacobi_omega must be in (0, 2), got ", p.jacobi_omega));
  if (name(p.solver) == "?") throw Error("set_params: unknown solver");
  d_.params = p;
}

}  // namespace pbd
