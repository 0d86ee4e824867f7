// Loading a big mesh body: a scene with one OBJ mesh (icosphere_mesh(level, 1), written to a temporary folder once)
// with stretch and bending, loaded (load_scene: OBJ check + tinyobjloader + topology + the reader's checks), built
// as a World<float> (build_world) and colored (num_colors), against a bare tinyobjloader parse of the same
// file (tinyobj::LoadObj, no triangulation, as load_obj calls it). Both run in every iteration, one after the other,
// so machine load hits both alike; after the benchmarks the program prints, per level, the median and min–max over
// the iterations of each figure and of the ratio (load + build + color) / (tinyobjloader parse).
//   bench_io_load [--benchmark_filter=/8]  (levels 6 and 8, 5 iterations each; level 8 is the 1.3M-triangle mesh)
#include "pbd/io/build_world.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/scene.hpp"

#include <benchmark/benchmark.h>
#include <tiny_obj_loader.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A temporary folder with NAME.obj (the icosphere) and NAME.json (a scene of it as one mesh body, stretch + bending),
// removed at exit.
class MeshFiles {
public:
  explicit MeshFiles(int level) {
    dir_ = std::filesystem::temp_directory_path() /
           ("pbd_bench_io_load_" + std::to_string(::getpid()) + "_" + std::to_string(level));
    std::filesystem::create_directories(dir_);
    const pbd::TriangleMesh mesh = pbd::icosphere_mesh(level, 1.0);
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(obj().c_str(), "w"), &std::fclose);
    if (!f) throw std::runtime_error("cannot write " + obj().string());
    std::fprintf(f.get(), "# icosphere level %d: %u vertices, %zu triangles\n", level, mesh.num_vertices(),
                 mesh.triangles.size());
    for (pbd::Index i = 0; i < mesh.num_vertices(); ++i)
      std::fprintf(f.get(), "v %.9g %.9g %.9g\n", mesh.positions(0, i), mesh.positions(1, i), mesh.positions(2, i));
    for (const auto& t : mesh.triangles) std::fprintf(f.get(), "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> s(std::fopen(scene().c_str(), "w"), &std::fclose);
    std::fprintf(s.get(), R"({"name": "icosphere%d", "dt": 0.01, "bodies": [{"type": "mesh", "obj": "%s",
  "stretch": {"stiffness": 1}, "bending": {"stiffness": 0.1}}]})",
                 level, obj().filename().c_str());
    triangles_ = mesh.triangles.size();
  }
  ~MeshFiles() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  std::filesystem::path obj() const { return dir_ / "mesh.obj"; }
  std::filesystem::path scene() const { return dir_ / "scene.json"; }
  std::size_t triangles() const { return triangles_; }

private:
  std::filesystem::path dir_;
  std::size_t triangles_ = 0;
};

// Per level, one entry per iteration: seconds of each figure.
struct Sample {
  double tinyobj, load, build, color;
  double ours() const { return load + build + color; }
};
std::map<int, std::vector<Sample>>& samples() {
  static std::map<int, std::vector<Sample>> s;
  return s;
}

double tinyobj_parse(const std::filesystem::path& file) {
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  const auto t0 = Clock::now();
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, file.c_str(), nullptr, /*triangulate=*/false))
    throw std::runtime_error("tinyobjloader: " + err);
  const double s = seconds_since(t0);
  benchmark::DoNotOptimize(attrib.vertices.data());
  return s;
}

void BM_LoadBuildColorVsTinyObj(benchmark::State& state) {
  const int level = int(state.range(0));
  const MeshFiles files(level);
  for (auto _ : state) {
    Sample s{};
    s.tinyobj = tinyobj_parse(files.obj());
    auto t0 = Clock::now();
    const pbd::Scene scene = pbd::load_scene(files.scene());
    s.load = seconds_since(t0);
    t0 = Clock::now();
    pbd::World<float> world = pbd::build_world<float>(scene.world);
    s.build = seconds_since(t0);
    t0 = Clock::now();
    world.num_colors();
    s.color = seconds_since(t0);
    state.SetIterationTime(s.ours());
    samples()[level].push_back(s);
    benchmark::DoNotOptimize(world.positions().data());
  }
  const auto& all = samples()[level];
  const std::size_t n = std::min<std::size_t>(all.size(), std::size_t(state.iterations()));
  double tiny = 0, load = 0, build = 0, color = 0;
  for (std::size_t i = all.size() - n; i < all.size(); ++i) {
    tiny += all[i].tinyobj;
    load += all[i].load;
    build += all[i].build;
    color += all[i].color;
  }
  state.counters["triangles"] = double(files.triangles());
  state.counters["tinyobj_s"] = tiny / double(n);
  state.counters["load_s"] = load / double(n);
  state.counters["build_s"] = build / double(n);
  state.counters["color_s"] = color / double(n);
  state.counters["ratio"] = (load + build + color) / tiny;
}
BENCHMARK(BM_LoadBuildColorVsTinyObj)->Arg(6)->Arg(8)->Iterations(5)->UseManualTime()->Unit(benchmark::kSecond);

// Median of `v` (sorted copy).
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void print_summary() {
  for (const auto& [level, all] : samples()) {
    auto figure = [&](const char* name, auto get) {
      std::vector<double> v;
      for (const Sample& s : all) v.push_back(get(s));
      std::printf("  %-34s median %8.3f  min %8.3f  max %8.3f\n", name, median(v), *std::min_element(v.begin(), v.end()),
                  *std::max_element(v.begin(), v.end()));
    };
    std::printf("icosphere level %d, %zu iterations (seconds; ratio = (load + build + color) / tinyobjloader, per "
                "iteration):\n", level, all.size());
    figure("tinyobjloader parse", [](const Sample& s) { return s.tinyobj; });
    figure("load_scene (OBJ, topology, checks)", [](const Sample& s) { return s.load; });
    figure("build_world<float>", [](const Sample& s) { return s.build; });
    figure("coloring (num_colors)", [](const Sample& s) { return s.color; });
    figure("load + build + color", [](const Sample& s) { return s.ours(); });
    figure("ratio", [](const Sample& s) { return s.ours() / s.tinyobj; });
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_summary();
  return 0;
}
