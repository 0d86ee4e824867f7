// Volumetric soft bodies: pbd.TetMesh and its sources (tet_box_mesh, load_tet_mesh, tetrahedralize), its checks and
// boundary (check_tet_mesh, tet_mesh_surface), the Neo-Hookean material (NeoHookeanMaterial, young_poisson), and
// World.add_tet_body / WorldDouble.add_tet_body returning a pbd.Body. The C++ side is io's tet_mesh.hpp,
// tet_mesh_reader.hpp, tetrahedralize.hpp, tet_body.hpp and engine's constraints/neo_hookean.hpp.
//
// Design:
// - A pbd.TetMesh is immutable and always valid: every way of making one checks it (the constructor runs
//   check_tet_mesh, the readers and generators check what they return). Its arrays are copies.
// - add_tet_body makes the constraint sets itself, as a scene's "tets" body does (scene.cpp, read_tets): a tet volume
//   set of the Stiffness given, a Neo-Hookean set of Stiffness.xpbd_compliance(material.compliance()) with each tet's
//   ratio = material.ratio(). So that a bad argument adds nothing (no orphan set, no half body), everything is
//   checked before the world is touched: the stiffnesses (check_stiffness) and the body itself, by a dry run of
//   pbd::add_tet_body without constraints into a scratch DescriptionBuilder (the C++ call's own checks and messages;
//   O(vertices)). What the dry run cannot see is a tet whose rest shape the world's precision cannot measure (a
//   sliver that float32 rounds flat): World::add then refuses it after the particles are in, as the C++ call does.
// - Array arguments are typed in the docstring signatures (numpy.ndarray[...]) but accept any array-like, checked by
//   the call as elsewhere in the module (arrays.hpp): a wrong shape or dtype is a ValueError naming the argument.
#include "arrays.hpp"
#include "bindings.hpp"
#include "signature.hpp"
#include "world_bindings.hpp"

#include "pbd/checks.hpp"
#include "pbd/constraints/neo_hookean.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/io/description_builder.hpp"
#include "pbd/io/tet_body.hpp"
#include "pbd/io/tet_mesh.hpp"
#include "pbd/io/tet_mesh_reader.hpp"
#include "pbd/io/tetrahedralize.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace pbd::python {

/// An array argument taken as it comes and checked by the call (real_array, numeric_array); `Name` is its type in
/// the docstring signature.
template <int Kind> struct ArrayArg {
  py::object object;
};
using RealRows = ArrayArg<0>;      // (N, 3) real numbers
using TriangleRows = ArrayArg<3>;  // (M, 3) integers
using TetRows = ArrayArg<4>;       // (T, 4) integers

}  // namespace pbd::python

namespace pybind11::detail {
template <int Kind> struct type_caster<pbd::python::ArrayArg<Kind>> {
  PYBIND11_TYPE_CASTER(pbd::python::ArrayArg<Kind>,
                       const_name<Kind == 0>(const_name("numpy.ndarray[numpy.float64[n, 3]]"),
                                             const_name<Kind == 3>(const_name("numpy.ndarray[numpy.int64[m, 3]]"),
                                                                   const_name("numpy.ndarray[numpy.int64[m, 4]]"))));
  bool load(handle src, bool) {
    if (!src) return false;
    value.object = reinterpret_borrow<object>(src);
    return true;
  }
  static handle cast(const pbd::python::ArrayArg<Kind>& a, return_value_policy, handle) {
    return a.object.inc_ref();
  }
};
}  // namespace pybind11::detail

namespace pbd::python {
namespace {

/// Rows of Index as a (rows, K) uint32 array (a copy).
template <std::size_t K> py::array_t<std::uint32_t> index_rows(const std::vector<std::array<Index, K>>& rows) {
  py::array_t<std::uint32_t> out({py::ssize_t(rows.size()), py::ssize_t(K)});
  auto r = out.template mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t k = 0; k < K; ++k) r(py::ssize_t(i), py::ssize_t(k)) = rows[i][k];
  return out;
}

/// A 3×N matrix of double from an (N, 3) array of real numbers.
Matrix3X<double> positions_arg(const RealRows& arg, const std::string& what) {
  const auto x = real_array<double>(arg.object, what, 3);
  return Eigen::Map<const Matrix3X<double>>(x.data(), 3, x.shape(0));
}

/// An (T, 4) array of vertex indices as tets (a ValueError for a wrong shape or dtype or an index < 0 or >= 2^32).
std::vector<std::array<Index, 4>> tets_arg(const TetRows& arg, const std::string& what) {
  py::array a = numeric_array(arg.object, what, "iu");
  if (a.ndim() != 2 || a.shape(1) != 4) throw py::value_error(what + " must have shape (T, 4), got " + shape_text(a));
  const auto t = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<std::array<Index, 4>> out(std::size_t(t.shape(0)));
  const std::int64_t* p = t.data();
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int k = 0; k < 4; ++k) {
      const std::int64_t v = p[4 * i + k];
      if (v < 0 || v > std::int64_t(UINT32_MAX))
        throw py::value_error(what + "[" + std::to_string(i) + "] must hold vertex indices >= 0, got " +
                              std::to_string(v));
      out[i][k] = Index(v);
    }
  return out;
}

/// The clamped face's axis and side ("x_min" ... "z_max", as a scene's "clamped"), else a ValueError.
std::pair<int, bool> face_arg(const std::string& face) {
  static constexpr const char* kFaces[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
  for (int f = 0; f < 6; ++f)
    if (face == kFaces[f]) return {f / 2, f % 2 == 1};
  throw py::value_error("add_tet_body: clamped must be \"x_min\", \"x_max\", \"y_min\", \"y_max\", \"z_min\" or "
                        "\"z_max\", got \"" + face + "\"");
}

template <class Real> void bind_tet_body(py::module_& m, const char* name) {
  using W = PyWorld<Real>;
  auto cls = py::reinterpret_borrow<py::class_<W>>(m.attr(name));
  cls.def(
      "add_tet_body",
      [](W& w, const TetMesh& mesh, const std::optional<NeoHookeanMaterial>& neo_hookean,
         const std::optional<Stiffness>& tet_volume, double density, double scale, const std::array<double, 3>& origin,
         const std::vector<std::int64_t>& pinned, const std::optional<std::string>& clamped,
         const std::optional<Stiffness>& stretch, const std::optional<Stiffness>& tet_fibers,
         const std::array<double, 3>& fiber_direction) {
        World<Real>& world = w.get("add_tet_body");
        w.check_no_views("add_tet_body");
        if (!neo_hookean && !tet_volume && !tet_fibers)
          throw Error("add_tet_body: a tet body needs neo_hookean, tet_volume or tet_fibers: without one nothing "
                      "holds it");
        TetBodyOptions options;
        options.scale = scale;
        options.origin = origin;
        options.density = density;
        for (std::size_t i = 0; i < pinned.size(); ++i)
          options.pinned.push_back(index_arg(pinned[i], "add_tet_body: pinned[" + std::to_string(i) + "]"));
        if (clamped) {
          const auto [axis, max] = face_arg(*clamped);
          const std::vector<Index> face = tet_mesh_face_vertices(mesh, axis, max);
          options.pinned.insert(options.pinned.end(), face.begin(), face.end());
        }
        // Everything checked before anything is added (the design note above).
        if (tet_volume) check_stiffness(*tet_volume, "add_tet_body: tet_volume");
        if (stretch) check_stiffness(*stretch, "add_tet_body: stretch");
        if (tet_fibers) check_stiffness(*tet_fibers, "add_tet_body: tet_fibers");
        TetConstraintSets sets;
        sets.direction = fiber_direction;
        if (neo_hookean) {
          check_stiffness(Stiffness::xpbd_compliance(neo_hookean->compliance()), "add_tet_body: neo_hookean");
          sets.ratio = neo_hookean->ratio();
          if (!std::isfinite(sets.ratio) || sets.ratio < 0.0)
            throw Error(detail::message("add_tet_body: ratio mu/lambda must be finite and >= 0, got ", sets.ratio));
        }
        DescriptionBuilder dry;
        TetConstraintSets direction_only;  // with the tet fibers, so that their direction is checked too
        direction_only.direction = fiber_direction;
        if (tet_fibers) direction_only.fibers = dry.add_constraint_set(*tet_fibers);
        add_tet_body(dry, mesh, options, direction_only);
        // The sets in the scene reader's order: tet volume, then Neo-Hookean.
        if (tet_volume) sets.volume = world.add_constraint_set(*tet_volume);
        if (neo_hookean)
          sets.neo_hookean = world.add_constraint_set(Stiffness::xpbd_compliance(neo_hookean->compliance()));
        if (stretch) sets.stretch = world.add_constraint_set(*stretch);
        if (tet_fibers) sets.fibers = world.add_constraint_set(*tet_fibers);
        return add_tet_body(world, mesh, options, sets);
      },
      py::arg("mesh"), py::kw_only(), py::arg("neo_hookean") = py::none(), py::arg("tet_volume") = py::none(),
      py::arg("density") = 1000.0, py::arg("scale") = 1.0,
      py::arg_v("origin", std::array<double, 3>{0.0, 0.0, 0.0}, "(0.0, 0.0, 0.0)"),
      py::arg_v("pinned", std::vector<std::int64_t>{}, "()"), py::arg("clamped") = py::none(),
      py::arg("stretch") = py::none(), py::arg("tet_fibers") = py::none(),
      py::arg_v("fiber_direction", std::array<double, 3>{1.0, 0.0, 0.0}, "(1.0, 0.0, 0.0)"),
      "Adds a TetMesh as a volumetric body and returns it (Body: first_particle, num_particles, its boundary "
      "triangles in world indices). Its vertices, scaled by `scale` and moved by `origin` (m), become particles "
      "with lumped masses (each tet gives density x volume / 4 kg to each corner; density in kg/m^3); `pinned` "
      "(mesh vertex indices) and, with clamped=\"x_min\", \"x_max\", \"y_min\", \"y_max\", \"z_min\" or \"z_max\", "
      "the vertices on that face of the mesh's bounding box are pinned. The constraint sets are made here, as a "
      "scene's \"tets\" body makes them: tet_volume=Stiffness puts a tet volume constraint on every tet in a new set "
      "of that stiffness; neo_hookean=NeoHookeanMaterial (e.g. young_poisson(E, nu)) puts a Neo-Hookean tet on every "
      "tet in a new set of Stiffness.xpbd_compliance(material.compliance()), each tet's ratio = material.ratio(). "
      "At least one of them or tet_fibers is needed. stretch=Stiffness puts one on every tet edge in a new set, after them: fibers when it "
      "is Stiffness.fiber(material), which tear the tets (a fiber that breaks takes the tets holding both its ends), "
      "else stretch constraints. tet_fibers=Stiffness puts a tet fiber on every tet along fiber_direction (in the "
      "mesh's frame) in a new set, last: with Stiffness.fiber(material) its curve is a stress in Pa (stiffness = "
      "Young's modulus E of the fibers), they yield, and a tet whose fibers break leaves the body (tet_fibers() "
      "reads their strains and stresses). Everything is checked first, so a bad argument raises pbd.Error and adds nothing.", sig);
}

}  // namespace

void bind_tets(py::module_& m) {
  py::class_<TetMesh>(m, "TetMesh",
                      "A tetrahedral mesh: vertex positions and positively oriented tets (pbd::TetMesh). Immutable "
                      "and always valid: made by TetMesh(positions, tets), tet_box_mesh, load_tet_mesh or "
                      "tetrahedralize, each of which checks it (check_tet_mesh).")
      .def(py::init([](const RealRows& positions, const TetRows& tets) {
             TetMesh mesh{positions_arg(positions, "TetMesh: positions"), tets_arg(tets, "TetMesh: tets")};
             check_tet_mesh(mesh, "TetMesh");
             return mesh;
           }),
           py::arg("positions"), py::arg("tets"),
           "A mesh of positions (V, 3) in m and tets (T, 4) of vertex indices (any integer dtype), each positively "
           "oriented: det[p1 - p0, p2 - p0, p3 - p0] > 0. Checked as check_tet_mesh(mesh, \"TetMesh\") does; a wrong "
           "shape or dtype is a ValueError.", sig)
      .def_property_readonly(
          "positions",
          [](const TetMesh& mesh) {
            py::array_t<double> out({py::ssize_t(mesh.num_vertices()), py::ssize_t(3)});
            std::copy(mesh.positions.data(), mesh.positions.data() + mesh.positions.size(), out.mutable_data());
            return out;
          },
          "vertex positions in m, (V, 3) float64 (a copy)")
      .def_property_readonly("tets", [](const TetMesh& mesh) { return index_rows(mesh.tets); },
                             "vertex indices of each tet, (T, 4) uint32 (a copy)")
      .def_property_readonly("num_vertices", &TetMesh::num_vertices, "number of vertices V")
      .def_property_readonly("num_tets", [](const TetMesh& mesh) { return mesh.tets.size(); }, "number of tets T")
      .def("__repr__", [](const TetMesh& mesh) {
        std::ostringstream o;
        o << "<pbd.TetMesh: " << mesh.num_vertices() << " vertices, " << mesh.tets.size() << " tets>";
        return o.str();
      }, sig);

  m.def("check_tet_mesh", &check_tet_mesh, py::arg("mesh"), py::arg("source"),
        "Checks a TetMesh: at least one tet, finite positions, every tet naming four distinct vertices in range and "
        "positively oriented, not degenerate (6V > 1e-9 x its longest edge^3). Raises pbd.Error starting with "
        "`source` and naming the first bad tet; a TetMesh already passed it when made.", sig);
  m.def("tet_mesh_surface", [](const TetMesh& mesh) { return index_rows(tet_mesh_surface(mesh)); }, py::arg("mesh"),
        "The boundary of a TetMesh: every face of exactly one tet, counter-clockwise seen from outside (a closed "
        "surface of positive volume), as (M, 3) uint32 vertex indices of the mesh.", sig);
  m.def("tet_box_mesh", &tet_box_mesh, py::arg("cells"), py::arg("size"),
        "A box of cells[0] x cells[1] x cells[2] cubes (each >= 1) spanning [0, size[0]] x [0, size[1]] x [0, size[2]] "
        "(m, each > 0), each cube cut into 6 tets (Kuhn); vertex (i, j, k) is (k (ny + 1) + j) (nx + 1) + i.", sig);
  m.def("load_tet_mesh", &load_tet_mesh, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
        "Loads a tet mesh: Gmsh .msh (ASCII or binary, 2.2 or 4.1) or TetGen .node/.ele (either file names the "
        "pair), keeping the nodes some tet names. pbd.Error names the file and the line of what is wrong.", sig);
  m.def(
      "tetrahedralize",
      [](const RealRows& surface_positions, const TriangleRows& triangles, double max_radius_edge_ratio,
         double max_volume, bool keep_surface, const std::string& source) {
        const TriangleMesh surface{positions_arg(surface_positions, "tetrahedralize: surface_positions"),
                                   triangles_arg(triangles.object, "tetrahedralize: triangles")};
        const TetrahedralizeOptions options{max_radius_edge_ratio, max_volume, keep_surface};
        py::gil_scoped_release release;
        return tetrahedralize(surface, options, source);
      },
      py::arg("surface_positions"), py::arg("triangles"), py::arg("max_radius_edge_ratio") = 1.5,
      py::arg("max_volume") = 0.0, py::arg("keep_surface") = true, py::arg("source") = "surface",
      "Fills a closed surface, positions (N, 3) in m and triangles (M, 3) counter-clockwise from outside, with "
      "tets by the tetgen program (scripts/deps installs it; releases the GIL). max_radius_edge_ratio (>= 1, tetgen "
      "-q): rounder tets and more of them when smaller; max_volume: largest tet in m^3 (0 = no limit); keep_surface: "
      "the surface's triangles are exactly the mesh's boundary (else tetgen may split them). The surface's vertices "
      "are the mesh's first ones. pbd.Error starts with `source`: a surface that is not closed, a bad option, tetgen "
      "missing or failing.", sig);

  py::class_<NeoHookeanMaterial>(m, "NeoHookeanMaterial",
                                 "Lame parameters of the Neo-Hookean tet energy (pbd::NeoHookeanMaterial): mu, the "
                                 "shear modulus, and lambda_, the hydrostatic modulus (lambda_Lame + mu), in Pa.")
      .def(py::init([](double mu, double lambda) {
             if (!std::isfinite(mu) || !(mu > 0.0))
               throw Error(detail::message("NeoHookeanMaterial: mu must be finite and > 0 Pa, got ", mu));
             if (!(lambda > 0.0))
               throw Error(
                   detail::message("NeoHookeanMaterial: lambda_ must be > 0 Pa (inf: incompressible), got ", lambda));
             return NeoHookeanMaterial{mu, lambda};
           }),
           py::arg("mu"), py::arg("lambda_"),
           "a material of mu > 0 and lambda_ > 0 in Pa (young_poisson makes one of E and nu)", sig)
      .def_readonly("mu", &NeoHookeanMaterial::mu, "shear modulus mu, Pa")
      .def_readonly("lambda_", &NeoHookeanMaterial::lambda, "hydrostatic modulus lambda (lambda_Lame + mu), Pa")
      .def("compliance", &NeoHookeanMaterial::compliance, "1/mu in 1/Pa: the XPBD compliance of its constraint set", sig)
      .def("ratio", &NeoHookeanMaterial::ratio, "mu/lambda: each Neo-Hookean tet's ratio (0: incompressible)", sig)
      .def("__repr__", [](const NeoHookeanMaterial& mat) {
        std::ostringstream o;
        o.precision(17);
        o << "pbd.NeoHookeanMaterial(mu=" << mat.mu << ", lambda_=" << mat.lambda << ")";
        return o.str();
      }, sig);
  m.def("young_poisson", &young_poisson, py::arg("young"), py::arg("poisson"),
        "The NeoHookeanMaterial of Young's modulus E > 0 (Pa) and Poisson's ratio nu in (-1, 0.5): mu = E / (2 (1 + "
        "nu)), lambda = E / (2 (1 + nu) (1 - 2 nu)); small strains then follow linear elasticity of E and nu.", sig);

  py::class_<Body>(m, "Body", "A body added to a world (pbd::Body): its particles and its boundary surface.")
      .def_readonly("first_particle", &Body::first_particle, "index of its first particle")
      .def_readonly("num_particles", &Body::num_particles, "number of its particles, consecutive from first_particle")
      .def_property_readonly("triangles", [](const Body& b) { return index_rows(b.triangles); },
                             "its surface triangles, (M, 3) uint32 particle indices (a copy)")
      .def("__repr__", [](const Body& b) {
        return "<pbd.Body: particles [" + std::to_string(b.first_particle) + ", " +
               std::to_string(b.first_particle + b.num_particles) + "), " + std::to_string(b.triangles.size()) +
               " triangles>";
      }, sig);

  bind_tet_body<float>(m, "World");
  bind_tet_body<double>(m, "WorldDouble");
}

}  // namespace pbd::python
