#pragma once
// pbd.World (float) and pbd.WorldDouble (double): one template, instantiated by world_float.cpp and
// world_double.cpp. The lifetime rules are in module.cpp's design note.
#include "arrays.hpp"
#include "bindings.hpp"
#include "params.hpp"
#include "signature.hpp"
#include "world_copy.hpp"
#include "world_core.hpp"
#include "world_edit.hpp"
#include "world_step.hpp"

#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/world.hpp"

#include <pybind11/stl.h>

#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

namespace pbd::python {

/// The Python argument of a constraint's rest value of type T: a float or None (then measured), or for a vector any
/// sequence of 3 numbers or None.
template <class T> using RestArg = std::conditional_t<std::is_arithmetic_v<T>, std::optional<T>, py::object>;
template <class C, std::size_t F> using FieldType = typename std::tuple_element_t<F, decltype(C::fields())>::type;

/// add_<kName>(<kParticleNames>..., set, <field names>=None...) for built-in type C: World::add<C> with the rest
/// values given, the others measured at the current positions (World::add's checks and messages).
template <class Real, class C, std::size_t... I, std::size_t... F>
void bind_add(py::class_<PyWorld<Real>>& cls, std::index_sequence<I...>, std::index_sequence<F...>) {
  using W = PyWorld<Real>;
  const std::string call = std::string("add_") + C::kName;
  std::string doc = "Adds a " + std::string(C::kNoun) + " on particles (";
  ((doc += (I ? ", " : "") + std::string(C::kParticleNames[I])), ...);
  doc += ") of a constraint set";
  for_each_field<C>([&](const auto& field, auto i) {
    doc += std::string(i ? ", " : "; ") + field.name + ": its " + field.noun;
  });
  doc += kNumFields<C> ? " (default: as they are now); returns its index." : "; returns its index.";
  cls.def(
      call.c_str(),
      [call](W& w, decltype(I, std::int64_t())... p, std::int64_t set, RestArg<FieldType<C, F>>... rest) {
        constexpr auto fields = C::fields();
        C c = blank_constraint<C>();
        ((c.particles[I] = index_arg(p, call + ": " + C::kParticleNames[I])), ...);
        c.set = index_arg(set, call + ": set");
        FieldMask given = 0;
        auto take = [&](const auto& field, auto& arg, std::size_t f) {
          auto& member = c.*field.member;
          if constexpr (std::is_arithmetic_v<std::decay_t<decltype(member)>>) {
            if (!arg) return;
            member = *arg;
          } else {
            if (arg.is_none()) return;
            member = vec3<Real>(arg, call + ": " + field.name);
          }
          given |= FieldMask(1) << f;
        };
        (take(std::get<F>(fields), rest, F), ...);
        return w.get(call.c_str()).add(c, given);
      },
      py::arg(C::kParticleNames[I])..., py::arg("set"), (py::arg(std::get<F>(C::fields()).name) = py::none())...,
      doc.c_str(), sig);
}

template <class Real> void bind_world(py::module_& m, const char* name, const char* build_name) {
  using W = PyWorld<Real>;
  using Vec = Vec3<Real>;
  const std::string precision = sizeof(Real) == 4 ? "float32" : "float64";
  py::class_<W> cls(m, name,
                    ("A simulated world in " + precision +
                     ": particles, constraints, colliders and the PBD step (pbd::World). kPinned = inf is the mass of a "
                     "pinned particle.").c_str());
  cls.attr("kPinned") = std::numeric_limits<Real>::infinity();
  cls.def(py::init<>(), "an empty world with default parameters", sig);

  // ---- particles ----
  cls.def(
      "add_particle",
      [](W& w, py::object position, double mass, py::object velocity) {
        w.check_no_views("add_particle");
        const Vec x = vec3<Real>(position, "add_particle: position");
        const Vec v = velocity.is_none() ? Vec::Zero() : vec3<Real>(velocity, "add_particle: velocity");
        auto& world = w.get("add_particle");
        return world.add_particle(x, mass_arg<Real>(mass, "add_particle", world.num_particles()), v);
      },
      py::arg("position"), py::arg("mass"), py::arg("velocity") = py::none(),
      "Adds a particle at position (m) with mass in kg (PINNED: fixed) and velocity (m/s); returns its index.", sig);
  cls.def(
      "add_particles",
      [](W& w, py::object positions, py::object masses) {
        w.check_no_views("add_particles");
        const auto x = real_array<Real>(positions, "add_particles: positions", 3);
        auto& world = w.get("add_particles");
        const VectorX<Real> M = masses_arg<Real>(masses, "add_particles", x.shape(0), world.num_particles());
        const Eigen::Map<const Matrix3X<Real>> X(x.data(), 3, x.shape(0));
        return world.add_particles(X, M);
      },
      py::arg("positions"), py::arg("masses"),
      "Adds N particles: positions (N, 3) in m, masses (N,) in kg (PINNED: fixed); returns the first index.", sig);
  cls.def(
      "set_mass",
      [](W& w, std::int64_t i, double mass) {
        const Index p = index_arg(i, "set_mass: particle");
        w.get("set_mass").set_mass(p, mass_arg<Real>(mass, "set_mass", p));
      },
      py::arg("particle"), py::arg("mass"), "Sets a particle's mass in kg (PINNED pins it).", sig);
  cls.def_property_readonly("num_particles", [](W& w) { return w.get("num_particles").num_particles(); },
                            "number of particles");
  cls.def_property(
      "time", [](W& w) { return w.get("time").time(); }, [](W& w, double t) { w.get("time").set_time(t); },
      "simulated time in s (dt per step)");

  // ---- views and copies ----
  cls.def(
      "positions",
      [](py::object self) {
        W& w = self.cast<W&>();
        auto x = w.get("positions").positions();
        return counted_view<Real>(self, &w.views, x.data(), x.cols());
      },
      ("Positions in m: an (N, 3) " + precision +
       " array viewing the world's storage (no copy), writeable between steps; add_particle(s) refuse while it lives.")
          .c_str(), sig);
  cls.def(
      "velocities",
      [](py::object self) {
        W& w = self.cast<W&>();
        auto v = w.get("velocities").velocities();
        return counted_view<Real>(self, &w.views, v.data(), v.cols());
      },
      ("Velocities in m/s: an (N, 3) " + precision +
       " array viewing the world's storage (no copy), writeable between steps; add_particle(s) refuse while it lives.")
          .c_str(), sig);
  cls.def(
      "inverse_masses",
      [](W& w) {
        const auto im = w.get("inverse_masses").inverse_masses();
        py::array_t<Real> out(im.size());
        std::copy(im.data(), im.data() + im.size(), out.mutable_data());
        return out;
      },
      "Inverse masses in 1/kg, (N,) (a copy; 0 = pinned).", sig);
  cls.def("num_views", [](const W& w) { return w.views; },
          "Number of live numpy views of positions()/velocities() (add_particle(s) need 0).", sig);

  // ---- constraints ----
  cls.def("add_constraint_set", [](W& w, const Stiffness& s) { return w.get("add_constraint_set").add_constraint_set(s); },
          py::arg("stiffness"), "Adds a constraint set with its Stiffness; returns its id.", sig);
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    bind_add<Real, C>(cls, std::make_index_sequence<C::kArity>{}, std::make_index_sequence<kNumFields<C>>{});
  });
  cls.def(
      "add_volume",
      [](W& w, py::object triangles, std::int64_t set, const std::optional<PressureSchedule>& pressure, std::optional<Real> rest) {
        const auto t = triangles_arg(triangles, "add_volume: triangles");
        return w.get("add_volume").add_volume(t, index_arg(set, "add_volume: set"), pressure.value_or(PressureSchedule{}), rest);
      },
      py::arg("triangles"), py::arg("set"), py::arg("pressure") = py::none(), py::arg("rest") = py::none(),
      "Adds a volume constraint on a closed mesh, triangles (M, 3) counter-clockwise from outside, its target "
      "pressure.at(time) x rest (pressure None: constant 1); rest in 6V m^3 (None: as it is now).", sig);
  cls.def(
      "add_tethers",
      [](W& w, py::object particles, const std::string& to, const std::string& length, double compliance) {
        py::array a = numeric_array(particles, "add_tethers: particles", "iu");
        if (a.ndim() != 1) throw py::value_error("add_tethers: particles must have shape (N,), got " + shape_text(a));
        const auto idx = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
        std::vector<Index> body(std::size_t(idx.shape(0)));
        for (std::size_t i = 0; i < body.size(); ++i)
          body[i] = index_arg(idx.data()[i], "add_tethers: particles[" + std::to_string(i) + "]");
        TetherOptions o;
        if (const auto t = parse_tether_to(to)) o.to = *t;
        else throw py::value_error("add_tethers: to must be \"nearest\" or \"all\", got \"" + to + "\"");
        if (const auto l = parse_tether_length(length)) o.length = *l;
        else throw py::value_error("add_tethers: length must be \"euclidean\" or \"geodesic\", got \"" + length + "\"");
        o.compliance = compliance;
        return w.get("add_tethers").add_tethers(body, o);
      },
      py::arg("particles"), py::arg("to") = "nearest", py::arg("length") = "euclidean", py::arg("compliance") = 0.0,
      "Adds long-range attachments: each of `particles` with mass and no anchor gets a one-sided tether to the nearest "
      "(to=\"nearest\") or every (\"all\") pinned or anchored particle among them, its length the straight "
      "(\"euclidean\") or along-the-stretch-constraints (\"geodesic\") rest distance, in a new set of XPBD "
      "compliance `compliance` (m/N). Returns how many were added (0 when none of the particles is pinned or anchored).", sig);
  cls.def("num_constraints", [](W& w) { return w.get("num_constraints").num_constraints(); },
          "Number of constraints of every type.", sig);

  // ---- colliders and contacts ----
  cls.def(
      "add_plane",
      [](W& w, py::object normal, Real offset, const std::optional<ContactMaterial<double>>& material) {
        w.get("add_plane").add_plane(vec3<Real>(normal, "add_plane: normal"), offset, to_engine<Real>(material.value_or(ContactMaterial<double>{})));
      },
      py::arg("normal"), py::arg("offset"), py::arg("material") = py::none(),
      "Adds the half-space normal.x >= offset (offset in m) with a ContactMaterial (None: no friction, no restitution).", sig);
  cls.def(
      "add_sphere",
      [](W& w, py::object center, Real radius, const std::optional<ContactMaterial<double>>& material) {
        w.get("add_sphere").add_sphere(vec3<Real>(center, "add_sphere: center"), radius, to_engine<Real>(material.value_or(ContactMaterial<double>{})));
      },
      py::arg("center"), py::arg("radius"), py::arg("material") = py::none(),
      "Adds a solid sphere: center in m, radius in m (> 0), with a ContactMaterial (None: no friction, no restitution).", sig);
  cls.def(
      "add_contact_body",
      [](W& w, std::int64_t first, std::int64_t count, Real radius, const std::optional<ContactMaterial<double>>& material, bool self,
         const std::vector<std::int64_t>& interior) {
        ContactBody<Real> b{index_arg(first, "add_contact_body: first"), index_arg(count, "add_contact_body: count"),
                            radius, to_engine<Real>(material.value_or(ContactMaterial<double>{})), self};
        for (std::int64_t i : interior) b.interior.push_back(index_arg(i, "add_contact_body: interior"));
        return w.get("add_contact_body").add_contact_body(b);
      },
      py::arg("first"), py::arg("count"), py::arg("radius"), py::arg("material") = py::none(),
      py::arg("self_collision") = false, py::arg("interior") = std::vector<std::int64_t>{},
      "Makes particles [first, first + count) a contact body of radius in m, its `interior` particles (ascending) "
      "points that touch colliders only; returns its index.", sig);

  // ---- stepping (world_step.hpp), editing (world_edit.hpp), copies and pickling (world_copy.hpp) ----
  bind_world_step<Real>(cls);
  bind_world_edit<Real>(cls);
  bind_world_copy<Real>(cls);

  cls.def("validate", [](W& w) { w.get("validate").validate(); },
          "Checks every invariant of the model; raises pbd.Error naming the first broken one.", sig);
  cls.def("__repr__", [name](W& w) {
    std::ostringstream o;
    o << "<pbd." << name << ": " << w.world.num_particles() << " particles, " << w.world.num_constraints()
      << " constraints, t = " << w.world.time() << " s>";
    return o.str();
  }, sig);

  // ---- scenes and metrics (module functions, overloaded on the precision as in metrics.hpp) ----
  m.def(
      build_name,
      [](const Scene& scene) {
        auto w = std::make_unique<W>();
        w->world = build_world<Real>(scene.world);
        return w;
      },
      py::arg("scene"), ("Builds a " + std::string(name) + " (" + precision + ") of a Scene, its parameters included.").c_str(), sig);
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    const std::string call = std::string(C::kName) + "_violation";
    m.def(call.c_str(), [call](W& w) { return violation_of<C>(w.get(call.c_str())); }, py::arg("world"),
          ("The violation of every " + std::string(C::kNoun) + " (Violation; reported in " + C::kMeasure.unit +
           " as " + C::kMeasure.key + " = violation x " + detail::message(C::kMeasure.scale) + ").").c_str(), sig);
  });
  m.def("constraint_violations", [](W& w) { return constraint_violations(w.get("constraint_violations")); },
        py::arg("world"), "The violation of every constraint type the world has (list of NamedViolation).", sig);
  m.def("energy", [](W& w) { return energy(w.get("energy")); }, py::arg("world"),
        "Kinetic and gravitational potential energy of the movable particles (Energy, J).", sig);
  m.def("position_hash", [](W& w) { return position_hash(w.get("position_hash")); }, py::arg("world"),
        "64-bit FNV-1a hash of the positions' bytes (int; `pbd run` prints it as 16 hex digits).", sig);
}

}  // namespace pbd::python
