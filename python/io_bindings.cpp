// Files: the built-in scenes by name (data_dir, load_scene, scene_names), frame writing (write_obj_frame,
// FrameSeries: io's frame_writer.hpp and frame_series.hpp) and the procedural meshes of mesh_generators.hpp.
//
// Where the data is (the installed layout, cmake/install.cmake): DIR/scenes/NAME.json under the first of
//   $PBD_DATA_DIR (when set, the only place looked at), sys.prefix/share/pbd, <module dir>/../share/pbd (the build
//   tree: build/release/share/pbd, made by cli/CMakeLists.txt) and <module dir>/../../../share/pbd (a module in
//   /usr/lib/python3/dist-packages: /usr/share/pbd)
// that has a scenes folder; the error names every place tried.
#include "arrays.hpp"
#include "bindings.hpp"
#include "signature.hpp"
#include "world_core.hpp"

#include "pbd/io/frame_series.hpp"
#include "pbd/io/frame_topology.hpp"
#include "pbd/io/frame_writer.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/scene.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace pbd::python {

namespace fs = std::filesystem;

namespace {

/// The places the data folder may be, in the order looked at.
std::vector<fs::path> data_dir_candidates() {
  if (const char* env = std::getenv("PBD_DATA_DIR"); env && *env) return {fs::path(env)};
  const fs::path prefix = py::module_::import("sys").attr("prefix").cast<std::string>();
  const fs::path module_dir = fs::path(py::module_::import("pbd").attr("__file__").cast<std::string>()).parent_path();
  return {prefix / "share" / "pbd", module_dir / ".." / "share" / "pbd", module_dir / ".." / ".." / ".." / "share" / "pbd"};
}

/// The data folder (with a scenes folder), else pbd.Error naming every place tried.
fs::path data_dir() {
  std::string tried;
  for (const fs::path& dir : data_dir_candidates()) {
    std::error_code ec;
    if (fs::is_directory(dir / "scenes", ec)) return fs::weakly_canonical(dir, ec);
    tried += (tried.empty() ? "" : ", ") + (dir / "scenes").string();
  }
  throw Error("pbd's data folder was not found: no scenes folder at " + tried +
              " (set PBD_DATA_DIR to the folder holding scenes/)");
}

/// (positions (V, 3) float64, triangles (M, 3) uint32) of a mesh.
py::tuple mesh_arrays(const TriangleMesh& mesh) {
  py::array_t<double> x({py::ssize_t(mesh.positions.cols()), py::ssize_t(3)});
  auto xr = x.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < mesh.positions.cols(); ++i)
    for (int k = 0; k < 3; ++k) xr(i, k) = mesh.positions(k, i);
  py::array_t<std::uint32_t> t({py::ssize_t(mesh.triangles.size()), py::ssize_t(3)});
  auto tr = t.mutable_unchecked<2>();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) tr(py::ssize_t(i), k) = mesh.triangles[i][std::size_t(k)];
  return py::make_tuple(x, t);
}

/// What a frame of `w` draws: the scene's bodies when given (a world built from it), else one body with `triangles`.
template <class Real>
FrameTopology topology_of(const World<Real>& w, const std::optional<Scene>& scene, py::object triangles,
                          const std::string& what) {
  if (scene) return frame_topology(w, scene->bodies);
  std::vector<std::array<Index, 3>> t;
  if (!triangles.is_none()) t = triangles_arg(triangles, what + ": triangles");
  return frame_topology(w, t);
}

/// f(world) for a World or a WorldDouble (a TypeError naming `what` for anything else).
template <class F> void with_world(py::handle obj, const char* what, F&& f) {
  if (py::isinstance<PyWorld<float>>(obj)) return f(obj.cast<PyWorld<float>&>().get(what));
  if (py::isinstance<PyWorld<double>>(obj)) return f(obj.cast<PyWorld<double>&>().get(what));
  throw py::type_error(std::string(what) + ": world must be a pbd.World or pbd.WorldDouble");
}

}  // namespace

void bind_io(py::module_& m) {
  m.def("data_dir", &data_dir,
        "The folder of pbd's data (scenes/ in it): $PBD_DATA_DIR, else sys.prefix/share/pbd, else share/pbd beside "
        "the module's install; pbd.Error names the places tried.",
        sig);
  m.def(
      "load_scene",
      [](const fs::path& name_or_path) {
        if (name_or_path.has_extension() || name_or_path.has_parent_path()) return load_scene(name_or_path);
        return load_scene_by_name(name_or_path.string(), data_dir() / "scenes");
      },
      py::arg("name_or_path"),
      "Loads a scene: a built-in one by name (e.g. \"cloth\"; scene_names() lists them) or a scene JSON file by "
      "path (docs/scenes.md). pbd.Error names the file and key, or lists the built-in scenes for an unknown name.",
      sig);
  m.def(
      "scene_names",
      [](std::optional<fs::path> directory) { return scene_names(directory ? *directory : data_dir() / "scenes"); },
      py::arg("directory") = py::none(), "Names of the scenes (NAME.json) in a folder (default: the built-in ones), sorted.",
      sig);

  py::class_<FrameSeries> series(
      m, "FrameSeries",
      "Frames of one simulation in one folder as `pbd run --frames` writes them: DIR/<stem>_<step>.obj or .vtu and "
      "for vtu DIR/<stem>.pvd (io's frame_series.hpp). Call finish() at the end.");
  series.def(py::init([](const fs::path& directory, const std::string& stem, const std::string& format,
                          std::optional<double> dt) {
               return dt ? FrameSeries(directory, stem, parse_frame_format(format), FrameTopology{}, *dt)
                         : FrameSeries(directory, stem, parse_frame_format(format), FrameTopology{});
             }),
             py::arg("directory"), py::arg("stem"), py::arg("format") = "vtu", py::arg("dt") = py::none(),
             "a series in an existing folder; format \"obj\" or \"vtu\". Frame times are step × dt: give the scene's "
             "dt (scene.dt), else the world's, which a float world rounds (90 steps of 1/60 s: 1.5000000782 s)", sig);
  series.def("finish", &FrameSeries::finish, "Writes the .pvd if frames were listed since it was last written.", sig);
  series.def("frame_file", &FrameSeries::frame_file, py::arg("step"), "DIR/<stem>_<step as %05d>.obj or .vtu", sig);
  series.def_property_readonly("pvd_file", &FrameSeries::pvd_file, "DIR/<stem>.pvd (written for vtu only)");
  series.def_property_readonly("frames_written", &FrameSeries::frames_written, "frames written so far");
  series.def(
      "write",
      [](FrameSeries& s, py::object world, long step, std::optional<Scene> scene, py::object triangles) {
        with_world(world, "FrameSeries.write", [&](const auto& w) {
          if (s.frames_written() == 0 || scene || !triangles.is_none())
            s.set_topology(topology_of(w, scene, triangles, "FrameSeries.write"));
          s.write(w, step);
        });
      },
      py::arg("world"), py::arg("step"), py::arg("scene") = py::none(), py::arg("triangles") = py::none(),
      "Writes the frame of `world` at `step` (>= 0) to frame_file(step) (for vtu, listed in the .pvd at the world's "
      "time). The first frame, and any given scene or triangles, set what is drawn, as write_obj_frame says.",
      sig);
  m.def(
      "write_obj_frame",
      [](const fs::path& file, py::object world, std::optional<Scene> scene, py::object triangles) {
        with_world(world, "write_obj_frame", [&](const auto& w) {
          write_obj_frame(file, w, topology_of(w, scene, triangles, "write_obj_frame"));
        });
      },
      py::arg("file"), py::arg("world"), py::arg("scene") = py::none(), py::arg("triangles") = py::none(),
      "Writes the world's positions as a Wavefront OBJ frame: the scene's bodies if it was built from `scene`, else "
      "one object with `triangles` (M, 3) and its stretch constraints off them as lines.",
      sig);

  m.def("grid_mesh", [](int n, double size) { return mesh_arrays(grid_mesh(n, size)); }, py::arg("resolution"),
        py::arg("size"), "An N x N grid in z = 0 over [0, size]^2 (open): (positions (V, 3), triangles (M, 3)).", sig);
  m.def("dodecahedron_mesh", [](double r) { return mesh_arrays(dodecahedron_mesh(r)); }, py::arg("radius"),
        "A closed dodecahedron of circumradius r, its pentagons fanned: (positions, triangles).", sig);
  m.def("icosphere_mesh", [](int level, double r) { return mesh_arrays(icosphere_mesh(level, r)); }, py::arg("level"),
        py::arg("radius"), "A closed icosphere subdivided `level` times (0..8): (positions, triangles).", sig);
  m.def(
      "tube_mesh",
      [](int segments, int rings, double r, double length, bool capped) {
        return mesh_arrays(tube_mesh(segments, rings, r, length, capped));
      },
      py::arg("segments"), py::arg("rings"), py::arg("radius"), py::arg("length"), py::arg("capped") = false,
      "A cylinder along z of `rings` rings of `segments` vertices, optionally capped: (positions, triangles).", sig);
}

}  // namespace pbd::python
