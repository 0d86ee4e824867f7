#pragma once
// Editing a World from Python beyond one constraint at a time: removal (remove_particle, remove_<type> for each
// built-in type), the generators of io's generators.hpp and mesh_body.hpp (add_cloth, add_rope, add_grains, add_mesh:
// a whole body and its constraints in one call), and each constraint's violation as a numpy array (violations).
#include "arrays.hpp"
#include "signature.hpp"
#include "world_core.hpp"

#include "pbd/constraint_types.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pbd::python {

/// A (N,) array of indices as a vector of Index (a ValueError naming `what` otherwise).
inline std::vector<Index> indices_arg(py::handle obj, const std::string& what) {
  if (py::array e = py::array::ensure(obj); e && e.ndim() == 1 && e.size() == 0) return {};  // () is float64 to numpy
  py::array a = numeric_array(obj, what, "iu");
  if (a.ndim() != 1) throw py::value_error(what + " must have shape (N,), got " + shape_text(a));
  const auto idx = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<Index> out(std::size_t(idx.shape(0)));
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = index_arg(idx.data()[i], what + "[" + std::to_string(i) + "]");
  return out;
}

/// The violation of each constraint of built-in type `type` (its header's `violation`; NaN for one it cannot
/// measure, such as a degenerate bending pair), in insertion order; nullopt for a name that is no built-in type.
template <class Real> std::optional<py::array_t<double>> violations_of(const World<Real>& world, const std::string& type) {
  std::optional<py::array_t<double>> out;
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto t, auto) {
    using C = typename decltype(t)::type;
    if (type != C::kName) return;
    const auto constraints = world.template constraints<C>();
    const auto x = world.positions();
    py::array_t<double> a(py::ssize_t(constraints.size()));
    double* d = a.mutable_data();
    for (const C& c : constraints) {
      const double e = violation(c, x);
      *d++ = e >= 0.0 ? e : std::numeric_limits<double>::quiet_NaN();
    }
    out = std::move(a);
  });
  return out;
}

/// Names of the built-in constraint types, comma-separated (for messages).
template <class Real> std::string builtin_type_names() {
  std::string names;
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto t, auto) {
    names += (names.empty() ? "" : ", ") + std::string(decltype(t)::type::kName);
  });
  return names;
}

template <class Real> void bind_world_edit(py::class_<PyWorld<Real>>& cls) {
  using W = PyWorld<Real>;
  cls.def(
      "remove_particle",
      [](W& w, std::int64_t i) { w.get("remove_particle").remove_particle(index_arg(i, "remove_particle: particle")); },
      py::arg("particle"),
      "Removes a particle from the simulation: every constraint on it goes, it is pinned where it is and never moves "
      "or collides again; its index stays valid. pbd.Error if a volume constraint uses it.",
      sig);
  for_each_type<BuiltinConstraintTypes<Real>>([&](auto t, auto) {
    using C = typename decltype(t)::type;
    const std::string call = std::string("remove_") + C::kName;
    cls.def(
        call.c_str(),
        [call](W& w, py::object indices) {
          const auto idx = indices_arg(indices, call + ": indices");
          w.get(call.c_str()).template remove_constraints<C>(idx);
        },
        py::arg("indices"),
        ("Removes the " + std::string(C::kNoun) + "s at `indices` (each at most once); later ones' indices move down "
         "as with list deletion, and the others keep their colors.").c_str(),
        sig);
  });
  cls.def(
      "violations",
      [](W& w, const std::string& type) {
        auto out = violations_of(std::as_const(w.get("violations")), type);
        if (!out) throw py::value_error("violations: no built-in constraint type \"" + type + "\"; the types are " +
                                        builtin_type_names<Real>());
        return *out;
      },
      py::arg("type"),
      "The violation of each constraint of a built-in type (e.g. \"stretch\"), in insertion order, as a float64 "
      "array in the type's own unit (as <type>_violation; NaN where not measurable).",
      sig);

  // ---- generators (io's generators.hpp, mesh_body.hpp) ----
  cls.def(
      "add_cloth",
      [](W& w, int resolution, double size, double mass, std::array<double, 3> origin, const std::string& pin,
         std::optional<std::int64_t> stretch_set) {
        w.check_no_views("add_cloth");
        ClothOptions o{resolution, size, mass, origin, ClothPin::corners};
        if (pin == "none") o.pin = ClothPin::none;
        else if (pin == "edge") o.pin = ClothPin::edge;
        else if (pin != "corners")
          throw py::value_error("add_cloth: pin must be \"none\", \"corners\" or \"edge\", got \"" + pin + "\"");
        std::optional<Index> set;
        if (stretch_set) set = index_arg(*stretch_set, "add_cloth: stretch_set");
        return add_cloth(w.get("add_cloth"), o, set);
      },
      py::arg("resolution") = 30, py::arg("size") = 1.0, py::arg("mass") = 1.0,
      py::arg_v("origin", std::array<double, 3>{0.0, 0.0, 1.0}, "(0.0, 0.0, 1.0)"), py::arg("pin") = "corners",
      py::arg("stretch_set") = py::none(),
      "Adds an N x N cloth (N = resolution) in the plane z = origin.z from origin over size m, total mass in kg; "
      "pin \"corners\" (the two corners at y = origin.y + size), \"edge\" or \"none\"; with stretch_set, a stretch "
      "constraint on every triangle edge (fibers in a set with a stress-strain curve, which tear). Particle (i, j) "
      "is first_particle + j N + i. Returns the Body.",
      sig);
  cls.def(
      "add_rope",
      [](W& w, int particles, double length, double mass, double end_mass, std::array<double, 3> origin,
         std::array<double, 3> direction, std::optional<std::int64_t> stretch_set) {
        w.check_no_views("add_rope");
        std::optional<Index> set;
        if (stretch_set) set = index_arg(*stretch_set, "add_rope: stretch_set");
        return add_rope(w.get("add_rope"), RopeOptions{particles, length, mass, end_mass, origin, direction}, set);
      },
      py::arg("particles") = 20, py::arg("length") = 1.0, py::arg("mass") = 1.0, py::arg("end_mass") = 1.0,
      py::arg_v("origin", std::array<double, 3>{0.0, 0.0, 1.0}, "(0.0, 0.0, 1.0)"),
      py::arg_v("direction", std::array<double, 3>{1.0, 0.0, 0.0}, "(1.0, 0.0, 0.0)"), py::arg("stretch_set") = py::none(),
      "Adds a rope of `particles` particles over length m from origin along direction, the first pinned; mass kg "
      "each but the last (end_mass); with stretch_set, a stretch constraint between neighbours. Returns the Body.",
      sig);
  cls.def(
      "add_grains",
      [](W& w, std::array<int, 3> count, double spacing, std::array<double, 3> origin, double jitter,
         std::uint64_t seed, double mass, std::array<double, 3> velocity) {
        w.check_no_views("add_grains");
        return add_grains(w.get("add_grains"), GrainsOptions{count, spacing, origin, jitter, seed, mass, velocity});
      },
      py::arg_v("count", std::array<int, 3>{1, 1, 1}, "(1, 1, 1)"), py::arg("spacing") = 0.1,
      py::arg_v("origin", std::array<double, 3>{0.0, 0.0, 0.0}, "(0.0, 0.0, 0.0)"), py::arg("jitter") = 0.1,
      py::arg("seed") = 1, py::arg("mass") = 1.0,
      py::arg_v("velocity", std::array<double, 3>{0.0, 0.0, 0.0}, "(0.0, 0.0, 0.0)"),
      "Adds nx x ny x nz loose particles (count) on a lattice of spacing m centred on origin's bottom layer, each moved "
      "by up to jitter x spacing (the same seed gives the same bits), mass kg each, at velocity m/s; no constraints. "
      "Returns the Body.",
      sig);
  cls.def(
      "add_mesh",
      [](W& w, py::object positions, py::object triangles, double scale, std::array<double, 3> origin, double mass,
         py::object pinned, std::optional<std::int64_t> stretch, std::optional<std::int64_t> bending,
         std::optional<std::int64_t> area, std::optional<std::int64_t> volume, std::optional<PressureSchedule> pressure) {
        w.check_no_views("add_mesh");
        const auto x = real_array<double>(positions, "add_mesh: positions", 3);
        TriangleMesh mesh{Eigen::Map<const Matrix3X<double>>(x.data(), 3, x.shape(0)),
                          triangles_arg(triangles, "add_mesh: triangles")};
        MeshBodyOptions o{scale, origin, mass, indices_arg(pinned, "add_mesh: pinned")};
        MeshConstraintSets sets;
        auto set = [](std::optional<std::int64_t> s, const char* what) -> std::optional<Index> {
          if (!s) return std::nullopt;
          return index_arg(*s, std::string("add_mesh: ") + what);
        };
        sets.stretch = set(stretch, "stretch");
        sets.bending = set(bending, "bending");
        sets.area = set(area, "area");
        sets.volume = set(volume, "volume");
        sets.pressure = pressure.value_or(PressureSchedule{});
        return add_mesh(w.get("add_mesh"), mesh, o, sets);
      },
      py::arg("positions"), py::arg("triangles"), py::arg("scale") = 1.0,
      py::arg_v("origin", std::array<double, 3>{0.0, 0.0, 0.0}, "(0.0, 0.0, 0.0)"), py::arg("mass") = 1.0,
      py::arg_v("pinned", py::tuple(), "()"), py::arg("stretch") = py::none(), py::arg("bending") = py::none(),
      py::arg("area") = py::none(), py::arg("volume") = py::none(), py::arg("pressure") = py::none(),
      "Adds a triangle mesh (positions (V, 3), triangles (M, 3); e.g. from icosphere_mesh) as a body scaled by `scale` "
      "and moved by origin (m), total mass kg spread evenly, `pinned` vertices pinned, and the constraints of each "
      "set given: stretch on every edge, bending on every interior edge, area on every triangle, one volume on the "
      "closed mesh (with `pressure`). The mesh is checked first, so a bad one adds nothing. Returns the Body.",
      sig);
}

}  // namespace pbd::python
