#include "pbd/io/description_builder.hpp"

#include "pbd/checks.hpp"
#include "pbd/closed_mesh.hpp"
#include "pbd/detail/message.hpp"

#include <string>

// Every check and message below is the engine's own (pbd/checks.hpp, closed_mesh.hpp, contacts.hpp), as World<double>
// runs them, applied to the description's arrays instead of a world's; the arithmetic is World<double>'s
// (tests/io/description_builder_test.cpp compares the two).
namespace pbd {

void DescriptionBuilder::set_mass(Index particle, double mass) {
  if (particle >= num_particles()) detail::fail_particle_index("set_mass: particle", particle, num_particles());
  check_mass(mass, "set_mass", particle);
  d_.inverse_masses[particle] = inverse_mass_of(mass);
}

Index DescriptionBuilder::add_particles(const Positions& positions, const VectorX<double>& masses) {
  const Index first = num_particles();
  check_particles(positions, masses, "add_particles", first);
  const Eigen::Index n = first + positions.cols();
  d_.positions.conservativeResize(3, n);
  d_.velocities.conservativeResize(3, n);
  d_.inverse_masses.conservativeResize(n);
  d_.positions.rightCols(positions.cols()) = positions;
  d_.velocities.rightCols(positions.cols()).setZero();
  for (Eigen::Index j = 0; j < positions.cols(); ++j) d_.inverse_masses[first + j] = inverse_mass_of(masses[j]);
  return first;
}

Index DescriptionBuilder::add_constraint_set(const Stiffness& stiffness) {
  check_stiffness(stiffness, detail::message("add_constraint_set: set ", d_.sets.size()));
  d_.sets.push_back(stiffness);
  return Index(d_.sets.size() - 1);
}

Index DescriptionBuilder::add_stretch(Index a, Index b, Index set, std::optional<double> rest) {
  return add(StretchConstraint<double>{{a, b}, set, rest.value_or(0.0)}, rest ? kAllFields : 0);
}

Index DescriptionBuilder::add_anchor(Index particle, Index set, std::optional<Vec> target) {
  return add(AnchorConstraint<double>{{particle}, set, target.value_or(Vec::Zero())}, target ? kAllFields : 0);
}

Index DescriptionBuilder::add_tethers(std::span<const Index> body, const TetherOptions& options) {
  check_tether_request(body, std::size_t(num_particles()), options, "add_tethers");
  const TetherInputs<double> in{body, &d_.positions, &d_.inverse_masses, d_.constraints<AnchorConstraint<double>>(),
                                d_.constraints<StretchConstraint<double>>()};
  const Index set = Index(d_.sets.size());  // the set made below, if any tether is made
  const std::vector<TetherConstraint<double>> tethers = plan_tethers(in, options, set);
  if (tethers.empty()) return 0;
  add_constraint_set(Stiffness::xpbd_compliance(options.compliance));
  reserve_more<TetherConstraint<double>>(tethers.size());
  for (const auto& t : tethers) add(t);
  return Index(tethers.size());
}

Index DescriptionBuilder::add_bending(Index p1, Index p2, Index p3, Index p4, Index set, std::optional<double> rest) {
  return add(BendingConstraint<double>{{p1, p2, p3, p4}, set, rest.value_or(0.0)}, rest ? kAllFields : 0);
}

Index DescriptionBuilder::add_area(Index a, Index b, Index c, Index set, std::optional<double> rest) {
  return add(AreaConstraint<double>{{a, b, c}, set, rest.value_or(0.0)}, rest ? kAllFields : 0);
}

Index DescriptionBuilder::add_volume(std::span<const std::array<Index, 3>> triangles, Index set,
                                     const PressureSchedule& pressure, std::optional<double> rest) {
  const char* item = "add_volume: volume constraint";
  const std::size_t index = d_.volumes.size();
  auto what = [&] { return detail::message(item, " ", index); };
  if (set >= d_.sets.size()) detail::fail_set_index(what(), set, d_.sets.size());
  const double r = checked_rest_volume<double>(triangles, d_.positions, pressure, rest, what());
  d_.volumes.push_back({{triangles.begin(), triangles.end()}, set, r, pressure});
  return Index(index);
}

void DescriptionBuilder::add_plane(const Vec& normal, double offset, const ContactMaterial<double>& material) {
  const double len = check_plane(normal, offset, material, detail::message("add_plane: plane ", d_.planes.size()));
  d_.planes.push_back({normal / len, offset / len, material});
}

void DescriptionBuilder::add_sphere(const Vec& center, double radius, const ContactMaterial<double>& material) {
  check_sphere(center, radius, material, detail::message("add_sphere: sphere ", d_.spheres.size()));
  d_.spheres.push_back({center, radius, material});
}

Index DescriptionBuilder::add_contact_body(const ContactBody<double>& body) {
  auto& bodies = d_.contact_bodies;
  const std::string what = detail::message("add_contact_body: body ", bodies.size());
  check_contact_body<double>(body, num_particles(), bodies, what);
  check_contact_reach<double>(body, d_.positions, d_.params.collision_margin, what);
  bodies.push_back(body);
  return Index(bodies.size() - 1);
}

void DescriptionBuilder::set_params(const StepParams<double>& p) {
  check_params(p);
  for (std::size_t b = 0; b < d_.contact_bodies.size(); ++b)
    check_contact_reach<double>(d_.contact_bodies[b], d_.positions, p.collision_margin,
                                detail::message("set_params: contact body ", b));
  d_.params = p;
}

void DescriptionBuilder::set_blocking(const BlockOptions& options) {
  if (options.constraints_per_block == 0) throw Error("set_blocking: constraints_per_block must be >= 1");
  d_.blocking = options;
}

}  // namespace pbd
