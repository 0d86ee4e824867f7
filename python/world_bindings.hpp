#pragma once
// pbd.World (float) and pbd.WorldDouble (double): one template, instantiated by world_float.cpp and
// world_double.cpp. The lifetime rules are in module.cpp's design note.
#include "arrays.hpp"
#include "bindings.hpp"
#include "params.hpp"

#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/world.hpp"

#include <pybind11/stl.h>

#include <atomic>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

namespace pbd::python {

/// A World as Python holds it: the engine's world, its live numpy views and whether it is stepping.
template <class Real> struct PyWorld {
  World<Real> world;
  int views = 0;                       // live views of positions()/velocities(); only touched with the GIL held
  std::atomic<bool> stepping = false;  // a step() runs with the GIL released

  /// The world, unless a step() runs on it in another thread.
  World<Real>& get(const char* call) {
    if (stepping) throw Error(std::string(call) + ": the world is stepping in another thread");
    return world;
  }
  /// Throws while a view of the storage that adding particles reallocates is alive.
  void check_no_views(const char* call) const {
    if (views)
      throw Error(std::string(call) + ": " + std::to_string(views) +
                  " numpy view(s) of positions()/velocities() are alive and adding particles moves the storage "
                  "they view; delete them (del) or keep copies (.copy()) first");
  }
};

/// Runs f(world) with the GIL released; the world refuses other calls meanwhile.
template <class Real, class F> void run_released(PyWorld<Real>& w, const char* call, F&& f) {
  World<Real>& world = w.get(call);
  struct Done {
    std::atomic<bool>& flag;
    ~Done() { flag = false; }  // after the GIL is taken back (destroyed after `release`)
  } done{w.stepping};
  w.stepping = true;
  // A live view may have been written since the last step: handing out a mutable map makes step() check that every
  // position and velocity is finite first (pbd::Error naming the particle otherwise).
  if (w.views) world.positions();
  py::gil_scoped_release release;
  f(world);
}

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
      doc.c_str());
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
  cls.def(py::init<>(), "an empty world with default parameters");

  // ---- particles ----
  cls.def(
      "add_particle",
      [](W& w, py::object position, Real mass, py::object velocity) {
        w.check_no_views("add_particle");
        const Vec x = vec3<Real>(position, "add_particle: position");
        const Vec v = velocity.is_none() ? Vec::Zero() : vec3<Real>(velocity, "add_particle: velocity");
        return w.get("add_particle").add_particle(x, mass, v);
      },
      py::arg("position"), py::arg("mass"), py::arg("velocity") = py::none(),
      "Adds a particle at position (m) with mass in kg (PINNED: fixed) and velocity (m/s); returns its index.");
  cls.def(
      "add_particles",
      [](W& w, py::object positions, py::object masses) {
        w.check_no_views("add_particles");
        const auto x = real_array<Real>(positions, "add_particles: positions", 3);
        const auto mass = real_array<Real>(masses, "add_particles: masses", 0, x.shape(0));
        const Eigen::Map<const Matrix3X<Real>> X(x.data(), 3, x.shape(0));
        const Eigen::Map<const VectorX<Real>> M(mass.data(), mass.shape(0));
        return w.get("add_particles").add_particles(X, M);
      },
      py::arg("positions"), py::arg("masses"),
      "Adds N particles: positions (N, 3) in m, masses (N,) in kg (PINNED: fixed); returns the first index.");
  cls.def(
      "set_mass", [](W& w, std::int64_t i, Real mass) { w.get("set_mass").set_mass(index_arg(i, "set_mass: particle"), mass); },
      py::arg("particle"), py::arg("mass"), "Sets a particle's mass in kg (PINNED pins it).");
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
          .c_str());
  cls.def(
      "velocities",
      [](py::object self) {
        W& w = self.cast<W&>();
        auto v = w.get("velocities").velocities();
        return counted_view<Real>(self, &w.views, v.data(), v.cols());
      },
      ("Velocities in m/s: an (N, 3) " + precision +
       " array viewing the world's storage (no copy), writeable between steps; add_particle(s) refuse while it lives.")
          .c_str());
  cls.def(
      "inverse_masses",
      [](W& w) {
        const auto im = w.get("inverse_masses").inverse_masses();
        py::array_t<Real> out(im.size());
        std::copy(im.data(), im.data() + im.size(), out.mutable_data());
        return out;
      },
      "Inverse masses in 1/kg, (N,) (a copy; 0 = pinned).");
  cls.def("num_views", [](const W& w) { return w.views; },
          "Number of live numpy views of positions()/velocities() (add_particle(s) need 0).");

  // ---- constraints ----
  cls.def("add_constraint_set", [](W& w, const Stiffness& s) { return w.get("add_constraint_set").add_constraint_set(s); },
          py::arg("stiffness"), "Adds a constraint set with its Stiffness; returns its id.");
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    bind_add<Real, C>(cls, std::make_index_sequence<C::kArity>{}, std::make_index_sequence<kNumFields<C>>{});
  });
  cls.def(
      "add_volume",
      [](W& w, py::object triangles, std::int64_t set, const PressureSchedule& pressure, std::optional<Real> rest) {
        const auto t = triangles_arg(triangles, "add_volume: triangles");
        return w.get("add_volume").add_volume(t, index_arg(set, "add_volume: set"), pressure, rest);
      },
      py::arg("triangles"), py::arg("set"), py::arg("pressure") = PressureSchedule{}, py::arg("rest") = py::none(),
      "Adds a volume constraint on a closed mesh, triangles (M, 3) counter-clockwise from outside; rest in 6V m^3.");
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
      "compliance `compliance` (m/N). Returns how many were added (0 when none of the particles is pinned or anchored).");
  cls.def("num_constraints", [](W& w) { return w.get("num_constraints").num_constraints(); },
          "Number of constraints of every type.");

  // ---- colliders and contacts ----
  cls.def(
      "add_plane",
      [](W& w, py::object normal, Real offset, const ContactMaterial<double>& material) {
        w.get("add_plane").add_plane(vec3<Real>(normal, "add_plane: normal"), offset, to_engine<Real>(material));
      },
      py::arg("normal"), py::arg("offset"), py::arg("material") = ContactMaterial<double>{},
      "Adds the half-space normal.x >= offset (offset in m) with a ContactMaterial.");
  cls.def(
      "add_sphere",
      [](W& w, py::object center, Real radius, const ContactMaterial<double>& material) {
        w.get("add_sphere").add_sphere(vec3<Real>(center, "add_sphere: center"), radius, to_engine<Real>(material));
      },
      py::arg("center"), py::arg("radius"), py::arg("material") = ContactMaterial<double>{},
      "Adds a solid sphere: center in m, radius in m (> 0), with a ContactMaterial.");
  cls.def(
      "add_contact_body",
      [](W& w, std::int64_t first, std::int64_t count, Real radius, const ContactMaterial<double>& material, bool self,
         const std::vector<std::int64_t>& interior) {
        ContactBody<Real> b{index_arg(first, "add_contact_body: first"), index_arg(count, "add_contact_body: count"),
                            radius, to_engine<Real>(material), self};
        for (std::int64_t i : interior) b.interior.push_back(index_arg(i, "add_contact_body: interior"));
        return w.get("add_contact_body").add_contact_body(b);
      },
      py::arg("first"), py::arg("count"), py::arg("radius"), py::arg("material") = ContactMaterial<double>{},
      py::arg("self_collision") = false, py::arg("interior") = std::vector<std::int64_t>{},
      "Makes particles [first, first + count) a contact body of radius in m, its `interior` particles (ascending) "
      "points that touch colliders only; returns its index.");

  // ---- stepping ----
  cls.def_property(
      "params", [](W& w) { return to_python(w.get("params").params()); },
      [](W& w, const StepParamsPy& p) {
        World<Real>& world = w.get("params");
        world.set_params(to_engine<Real>(p, world.params()));
      },
      "step parameters (StepParams; a copy: change it, then assign it back)");
  cls.def(
      "step", [](W& w) { run_released(w, "step", [](World<Real>& world) { world.step(); }); },
      "Advances the world by params.dt s (releases the GIL).");
  cls.def(
      "step",
      [](W& w, py::object forces) {
        const Index n = w.get("step").num_particles();
        const auto f = real_array<Real>(forces, "step: forces", 3, py::ssize_t(n));
        const Eigen::Map<const Matrix3X<Real>> F(f.data(), 3, f.shape(0));
        run_released(w, "step", [&](World<Real>& world) { world.step(F); });
      },
      py::arg("forces"), "Advances the world by params.dt s with forces (N, 3) in N on the particles (releases the GIL).");
  cls.def("last_step_stats", [](W& w) { return w.get("last_step_stats").last_step_stats(); },
          "Statistics of the last step() (StepStats, a copy).");
  // Readings of a type that follows a curve (World::material_readings) as a dict of numpy arrays.
  auto readings = [](const std::vector<FiberReading>& r) {
    py::array_t<double> strain(py::ssize_t(r.size())), plastic(py::ssize_t(r.size())), force(py::ssize_t(r.size()));
    for (std::size_t i = 0; i < r.size(); ++i) {
      strain.mutable_at(i) = r[i].strain;
      plastic.mutable_at(i) = r[i].plastic;
      force.mutable_at(i) = r[i].force;
    }
    py::dict out;
    out["strain"] = strain;
    out["plastic"] = plastic;
    out["force"] = force;
    return out;
  };
  cls.def(
      "fibers", [readings](W& w) { return readings(w.get("fibers").fibers()); },
      "Each fiber after the last step, in insertion order: a dict of numpy arrays 'strain' (total, l/L0 - 1), "
      "'plastic' (plastic strain) and 'force' (tension in N, -lambda/h^2; NaN before a step or in a PBD set).");
  cls.def(
      "tet_fibers",
      [readings](W& w) {
        return readings(w.get("tet_fibers").template material_readings<TetFiberConstraint<Real>>());
      },
      "Each tet fiber after the last step, in insertion order: a dict of numpy arrays 'strain' (total, |F a0| - 1), "
      "'plastic' (plastic strain) and 'force' (the stress along it in Pa, -lambda/(h^2 V0); NaN before a step or in "
      "a PBD set).");
  cls.def(
      "last_breaks",
      [](W& w) {
        const auto b = w.get("last_breaks").last_breaks();
        return std::vector<FiberBreak>(b.begin(), b.end());
      },
      "The fibers and tet fibers the last step broke (FiberBreak list: fibers first, each type in the order of their "
      "indices just before).");
  cls.def(
      "add_surface",
      [](W& w, const std::vector<std::array<Index, 3>>& triangles) { return w.get("add_surface").add_surface(triangles); },
      py::arg("triangles"),
      "Adds a surface that tears: where fibers on its edges break, the particles along the cut are copied so that "
      "it parts (mass split by the triangles on each side). Returns its index.");
  cls.def(
      "surface",
      [](W& w, Index s) {
        const auto t = w.get("surface").surface(s);
        return std::vector<std::array<Index, 3>>(t.begin(), t.end());
      },
      py::arg("s"), "The triangles of surface s as they are now (particles renamed where it tore).");
  cls.def(
      "last_copies",
      [](W& w) {
        std::vector<std::pair<Index, Index>> out;
        for (const TornParticle& t : w.get("last_copies").last_copies()) out.push_back({t.particle, t.from});
        return out;
      },
      "The particles the last step's tears added, as (particle, copied from) pairs.");
  cls.def("set_measure_violation", [](W& w, bool on) { w.get("set_measure_violation").set_measure_violation(on); },
          py::arg("on"), "Whether step() measures each type's violation into last_step_stats().violation.");
  cls.def("validate", [](W& w) { w.get("validate").validate(); },
          "Checks every invariant of the model; raises pbd.Error naming the first broken one.");
  cls.def("__repr__", [name](W& w) {
    std::ostringstream o;
    o << "<pbd." << name << ": " << w.world.num_particles() << " particles, " << w.world.num_constraints()
      << " constraints, t = " << w.world.time() << " s>";
    return o.str();
  });

  // ---- scenes and metrics (module functions, overloaded on the precision as in metrics.hpp) ----
  m.def(
      build_name,
      [](const Scene& scene) {
        auto w = std::make_unique<W>();
        w->world = build_world<Real>(scene.world);
        return w;
      },
      py::arg("scene"), ("Builds a " + std::string(name) + " (" + precision + ") of a Scene, its parameters included.").c_str());
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    const std::string call = std::string(C::kName) + "_violation";
    m.def(call.c_str(), [call](W& w) { return violation_of<C>(w.get(call.c_str())); }, py::arg("world"),
          ("The violation of every " + std::string(C::kNoun) + " (Violation; reported in " + C::kMeasure.unit +
           " as " + C::kMeasure.key + " = violation x " + detail::message(C::kMeasure.scale) + ").").c_str());
  });
  m.def("constraint_violations", [](W& w) { return constraint_violations(w.get("constraint_violations")); },
        py::arg("world"), "The violation of every constraint type the world has (list of NamedViolation).");
  m.def("energy", [](W& w) { return energy(w.get("energy")); }, py::arg("world"),
        "Kinetic and gravitational potential energy of the movable particles (Energy, J).");
  m.def("position_hash", [](W& w) { return position_hash(w.get("position_hash")); }, py::arg("world"),
        "64-bit FNV-1a hash of the positions' bytes (int; `pbd run` prints it as 16 hex digits).");
}

}  // namespace pbd::python
