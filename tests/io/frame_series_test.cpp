// Frame series (frame_series.hpp): the stem check, the format names, OBJ frames with one object per body, VTU
// frames of one piece with a body id per point and cell whose binary arrays decode to the world's values bit for
// bit, cell arrays only for the constraint types the scene has, the .pvd listing every frame with its time
// (step × dt), and failed writes that leave nothing behind: no frame of a non-finite state, no frame written into
// a FIFO or device that took a frame's name, no temporary of a killed run left once the next one prepares.
#include "error_checks.hpp"
#include "pbd/detail/fault_injection.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/frame_series.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"
#include "file_size_limit.hpp"
#include "temp_dir.hpp"
#include "vtu_text.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <new>
#include <sstream>
#include <string>
#include <vector>

namespace pbd {
namespace {

using test::count_of;
using test::data_array;
using test::text_of;

// A 3×3 cloth with stretch and area (particles 0-8) and a 4-particle rope with stretch (9-12), as a scene.
const char* kScene = R"({"name": "two", "dt": 0.01, "bodies": [
    {"type": "cloth", "resolution": 3, "stretch": {}, "area": {}},
    {"type": "rope", "particles": 4, "origin": [0.25, -0.5, 2.0], "stretch": {}}]})";

template <class Real> struct TwoBodies {
  Scene scene = parse_scene(kScene, "two.json");
  World<Real> world = build_world<Real>(scene.world);
  FrameTopology topology = frame_topology(world, scene.bodies);
};

std::size_t files_in(const std::filesystem::path& dir) {
  return std::size_t(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()));
}

TEST(FrameSeries, TheStemMustBeAPlainFileName) {
  for (const std::string& bad : std::vector<std::string>{"", ".", "..", "a/b", "../up", "a\\b", "new\nline",
                                                       std::string("nul\0x", 5), "del\x7f"}) {
    const std::string e = test::error_of([&] { check_frame_stem(bad); });
    test::expect_words(e, {"frame file stem", "not a plain file name"});
    const test::TempDir dir("pbd_frame_series");
    EXPECT_THROW(FrameSeries(dir.path(), bad, FrameFormat::obj, {}), Error) << e;
  }
  test::expect_words(test::error_of([&] { check_frame_stem("a/b"); }), {"\"a/b\"", "'/'"});
  test::expect_words(test::error_of([&] { check_frame_stem("new\nline"); }), {"\"new\\x0aline\"", "control"});
  for (const std::string good : {"cloth", "cloth-fold", "a.b", "..a", "name with spaces"})
    EXPECT_NO_THROW(check_frame_stem(good)) << good;
}

TEST(FrameSeries, ParseFrameFormatNamesTheValidOnes) {
  EXPECT_EQ(parse_frame_format("obj"), FrameFormat::obj);
  EXPECT_EQ(parse_frame_format("vtu"), FrameFormat::vtu);
  EXPECT_STREQ(name(FrameFormat::vtu), "vtu");
  test::expect_words(test::error_of([] { parse_frame_format("ply"); }), {"\"ply\"", "obj", "vtu"});
}

TEST(FrameSeries, ObjFramesHaveOneObjectPerBody) {
  TwoBodies<float> s;
  const test::TempDir dir("pbd_frame_series");
  FrameSeries series(dir.path(), "two", FrameFormat::obj, s.topology);
  series.write(s.world, 0);
  s.world.step();
  series.write(s.world, 1);
  EXPECT_EQ(series.frames_written(), 2u);
  EXPECT_EQ(series.frame_file(1), dir / "two_00001.obj");
  EXPECT_EQ(files_in(dir.path()), 2u) << "two frames, no .pvd for OBJ";
  std::istringstream in(text_of(dir / "two_00001.obj"));
  std::vector<std::string> objects;
  std::vector<std::vector<std::string>> kinds;  // per object, the first word of each of its lines
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("o ", 0) == 0) {
      objects.push_back(line.substr(2));
      kinds.emplace_back();
    } else if (!kinds.empty()) {
      kinds.back().push_back(line.substr(0, line.find(' ')));
    }
  }
  ASSERT_EQ(objects, (std::vector<std::string>{"cloth_0", "rope_1"}));
  EXPECT_EQ(std::count(kinds[0].begin(), kinds[0].end(), "v"), 9);
  EXPECT_EQ(std::count(kinds[0].begin(), kinds[0].end(), "f"), 8);
  EXPECT_EQ(std::count(kinds[0].begin(), kinds[0].end(), "l"), 0);
  EXPECT_EQ(std::count(kinds[1].begin(), kinds[1].end(), "v"), 4);
  EXPECT_EQ(std::count(kinds[1].begin(), kinds[1].end(), "f"), 0);
  EXPECT_EQ(std::count(kinds[1].begin(), kinds[1].end(), "l"), 3);
  EXPECT_NE(text_of(dir / "two_00001.obj").find("o rope_1\nv 0.25 -0.5 2"), std::string::npos)
      << "the rope's vertices follow its object line";
}

template <class Real> class FrameSeriesVtu : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(FrameSeriesVtu, Precisions);

TYPED_TEST(FrameSeriesVtu, OnePieceWithABodyIdPerPointAndCellAndTheWorldsValuesBitForBit) {
  using Real = TypeParam;
  TwoBodies<Real> s;
  for (int i = 0; i < 5; ++i) s.world.step();
  const test::TempDir dir("pbd_frame_series");
  FrameSeries series(dir.path(), "two", FrameFormat::vtu, s.topology);
  series.write(s.world, 5);
  const std::string vtu = text_of(dir / "two_00005.vtu");
  EXPECT_EQ(count_of(vtu, "<Piece "), 1u);
  EXPECT_NE(vtu.find("<Piece NumberOfPoints=\"13\" NumberOfCells=\"11\">"), std::string::npos);
  EXPECT_NE(vtu.find("bodies (the body arrays): 0 cloth_0, 1 rope_1 -->"), std::string::npos);
  EXPECT_NE(vtu.find(std::string("type=\"") + (sizeof(Real) == 4 ? "Float32" : "Float64") + "\" Name=\"positions\""),
            std::string::npos);
  // Per point and per cell, the body: the cloth's 9 particles and 8 triangles, then the rope's 4 and 3 lines.
  std::vector<std::int32_t> point_body(13, 0), cell_body(11, 0);
  std::fill(point_body.begin() + 9, point_body.end(), 1);
  std::fill(cell_body.begin() + 8, cell_body.end(), 1);
  EXPECT_EQ(data_array<std::int32_t>(vtu, "body", 0), point_body);
  EXPECT_EQ(data_array<std::int32_t>(vtu, "body", 1), cell_body);
  // Every particle in world order: positions, velocities and inverse masses exactly; the pinned ones marked.
  const auto x = s.world.positions();
  const auto v = s.world.velocities();
  const auto w = s.world.inverse_masses();
  const auto points = data_array<Real>(vtu, "positions", 0);
  const auto velocity = data_array<Real>(vtu, "velocity", 0);
  const auto inverse_mass = data_array<Real>(vtu, "inverse_mass", 0);
  const auto pinned = data_array<std::uint8_t>(vtu, "pinned", 0);
  ASSERT_EQ(points.size(), 39u);
  ASSERT_EQ(velocity.size(), 39u);
  ASSERT_EQ(inverse_mass.size(), 13u);
  ASSERT_EQ(pinned.size(), 13u);
  for (Index i = 0; i < 13; ++i) {
    EXPECT_EQ(inverse_mass[i], w[i]);
    EXPECT_EQ(pinned[i], w[i] == Real(0) ? 1 : 0) << i;
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(points[3 * i + d], x(d, i)) << i;
      EXPECT_EQ(velocity[3 * i + d], v(d, i)) << i;
    }
  }
  EXPECT_EQ(pinned[9], 1) << "the rope's first particle";
  // Connectivity in world indices: the cloth's triangles, then the rope's lines 9-10, 10-11, 11-12.
  const auto cells = test::cells_of(vtu);
  ASSERT_EQ(cells.size(), 11u);
  for (std::size_t k = 0; k < 8; ++k) {
    const auto& t = s.topology.bodies[0].triangles[k];
    EXPECT_EQ(cells[k], (std::vector<std::int64_t>{t[0], t[1], t[2]})) << "triangle " << k;
  }
  EXPECT_EQ(std::vector(cells.begin() + 8, cells.end()),
            (std::vector<std::vector<std::int64_t>>{{9, 10}, {10, 11}, {11, 12}}));
  std::vector<std::uint8_t> types(8, 5);
  types.insert(types.end(), 3, 3);
  EXPECT_EQ(data_array<std::uint8_t>(vtu, "types", 0), types);
  // Cell data: a line's stretch is its constraint's; a triangle's the largest of its edges'; area NaN on lines.
  const auto stretch = s.world.template constraints<StretchConstraint<Real>>();
  const auto area = s.world.template constraints<AreaConstraint<Real>>();
  const PositionsView<Real> xv(x);
  const auto stretch_cells = data_array<double>(vtu, "stretch", 0);
  const auto area_cells = data_array<double>(vtu, "area", 0);
  const auto rope_stretch = test::of_body(stretch_cells, cell_body, 1);
  ASSERT_EQ(rope_stretch.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rope_stretch[k], violation(stretch[stretch.size() - 3 + k], xv));
  for (double a : test::of_body(area_cells, cell_body, 1)) EXPECT_TRUE(std::isnan(a));
  const auto cloth_stretch = test::of_body(stretch_cells, cell_body, 0);
  const auto cloth_area = test::of_body(area_cells, cell_body, 0);
  ASSERT_EQ(cloth_stretch.size(), 8u);
  ASSERT_EQ(cloth_area.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) {
    const auto& t = s.topology.bodies[0].triangles[k];
    double largest = -1;
    for (std::size_t c = 0; c < stretch.size(); ++c)
      for (int e = 0; e < 3; ++e) {
        const std::array<Index, 2> edge{t[e], t[(e + 1) % 3]};
        if (stretch[c].particles == edge || stretch[c].particles == std::array<Index, 2>{edge[1], edge[0]})
          largest = std::max(largest, violation(stretch[c], xv));
      }
    EXPECT_EQ(cloth_stretch[k], largest) << "triangle " << k;
    EXPECT_EQ(cloth_area[k], violation(area[k], xv)) << "triangle " << k << " (one area constraint per triangle)";
  }
  EXPECT_EQ(data_array<double>(vtu, "TimeValue", 0), std::vector<double>{5 * double(s.world.params().dt)});
}

// A frame carries a measure's array only when the world has its constraints: the two-body scene without its area
// constraints has no area array (with them, TwoBodies above, it has), grains have neither stretch nor area.
TEST(FrameSeries, ACellArrayOnlyForTheConstraintTypesTheSceneHas) {
  auto frame = [](const char* json) {
    const Scene scene = parse_scene(json, "s.json");
    const World<float> world = build_world<float>(scene.world);
    const FrameTopology t = frame_topology(world, scene.bodies);
    return vtu_frame(world, t, vtu_cell_constraints(world, t), "f.vtu");
  };
  const std::string with = frame(kScene);
  const std::string without = frame(R"({"name": "two", "dt": 0.01, "bodies": [
      {"type": "cloth", "resolution": 3, "stretch": {}},
      {"type": "rope", "particles": 4, "origin": [0.25, -0.5, 2.0], "stretch": {}}]})");
  const std::string grains = frame(R"({"name": "g", "dt": 0.01, "bodies": [
      {"type": "grains", "count": [2, 2, 1], "spacing": 0.1}]})");
  EXPECT_EQ(count_of(with, "Name=\"area\""), 1u);
  EXPECT_EQ(count_of(with, "Name=\"stretch\""), 1u);
  EXPECT_EQ(count_of(without, "Name=\"area\""), 0u);
  EXPECT_EQ(count_of(without, "Name=\"stretch\""), 1u);
  EXPECT_NE(without.find("<CellData Scalars=\"stretch\">"), std::string::npos);
  for (const char* name : {"stretch", "area", "volume_ratio", "strain", "fiber_strain", "tet_fiber_strain"})
    EXPECT_EQ(count_of(grains, std::string("Name=\"") + name + "\""), 0u) << name;
  EXPECT_NE(grains.find("<CellData Scalars=\"body\">"), std::string::npos) << "no measure: coloured by body";
  for (const std::string* vtu : {&with, &without, &grains})
    EXPECT_EQ(count_of(*vtu, "Name=\"body\""), 2u) << "per point and per cell";
}

TEST(FrameSeries, ABodyWithoutTrianglesOrLinesIsDrawnAsVertices) {
  const Scene scene = parse_scene(R"({"name": "g", "dt": 0.01, "bodies": [
      {"type": "grains", "count": [2, 2, 1], "spacing": 0.1}]})", "g.json");
  const World<float> world = build_world<float>(scene.world);
  const test::TempDir dir("pbd_frame_series");
  FrameSeries(dir.path(), "g", FrameFormat::vtu, frame_topology(world, scene.bodies)).write(world, 0);
  const std::string vtu = text_of(dir / "g_00000.vtu");
  EXPECT_NE(vtu.find("<Piece NumberOfPoints=\"4\" NumberOfCells=\"4\">"), std::string::npos);
  EXPECT_EQ(data_array<std::uint8_t>(vtu, "types", 0), std::vector<std::uint8_t>(4, 1));
  EXPECT_EQ(test::cells_of(vtu), (std::vector<std::vector<std::int64_t>>{{0}, {1}, {2}, {3}}));
}

TEST(FrameSeries, ThePvdListsEveryFrameWrittenSoFarWithItsTime) {
  TwoBodies<double> s;
  const test::TempDir dir("pbd_frame_series");
  FrameSeries series(dir.path(), "two", FrameFormat::vtu, s.topology);
  std::vector<double> times;
  for (int step = 0; step <= 6; ++step) {
    if (step % 3 == 0) {
      series.write(s.world, step);
      times.push_back(step * 0.01);  // step × dt
      // Rewritten after each frame: a run stopped here leaves a series of the frames so far.
      EXPECT_EQ(count_of(text_of(series.pvd_file()), "<DataSet "), times.size());
    }
    s.world.step();
  }
  EXPECT_EQ(series.pvd_file(), dir / "two.pvd");
  const std::string pvd = text_of(series.pvd_file());
  EXPECT_NE(pvd.find("<VTKFile type=\"Collection\""), std::string::npos);
  for (std::size_t k = 0; k < times.size(); ++k) {
    char entry[160];
    std::snprintf(entry, sizeof entry, "<DataSet timestep=\"%.17g\" part=\"0\" file=\"two_%05zu.vtu\"/>", times[k], 3 * k);
    EXPECT_NE(pvd.find(entry), std::string::npos) << entry << "\n" << pvd;
  }
  EXPECT_DOUBLE_EQ(times[2], 6 * 0.01);
  EXPECT_EQ(files_in(dir.path()), 4u) << "three frames and the .pvd, no temporaries";
  // The same step written again replaces its entry.
  series.write(s.world, 6);
  EXPECT_EQ(count_of(text_of(series.pvd_file()), "<DataSet "), 3u);
}

// A frame's time is step × dt in double: the scene's dt when the series is given it (a World<float> steps by
// float(1/60), so 90 of its steps are 1.5000000782 s), else the world's (a World<double>'s 1/60: exactly 1.5 at
// step 90, where 90 steps summed give 1.4999999999999996).
TEST(FrameSeries, FrameTimesAreTheStepCountTimesDtWrittenExactly) {
  const char* json = R"({"name": "r", "dt": 0.016666666666666666, "bodies": [{"type": "rope", "particles": 3}]})";
  const Scene scene = parse_scene(json, "r.json");
  auto times_of = [](const test::TempDir& dir) {
    const std::string pvd = text_of(dir / "r.pvd");
    const std::string vtu = text_of(dir / "r_00090.vtu");
    return std::pair{pvd, data_array<double>(vtu, "TimeValue", 0)};
  };
  {
    World<float> world = build_world<float>(scene.world);
    ASSERT_NE(90 * double(world.params().dt), 1.5) << "float(1/60) × 90";
    const test::TempDir dir("pbd_frame_series");
    FrameSeries series(dir.path(), "r", FrameFormat::vtu, frame_topology(world, scene.bodies), scene.world.params.dt);
    series.write(world, 90);
    const auto [pvd, time] = times_of(dir);
    EXPECT_NE(pvd.find("<DataSet timestep=\"1.5\" part=\"0\" file=\"r_00090.vtu\"/>"), std::string::npos) << pvd;
    EXPECT_EQ(time, std::vector<double>{1.5});
  }
  {
    World<double> world = build_world<double>(scene.world);
    const test::TempDir dir("pbd_frame_series");
    FrameSeries series(dir.path(), "r", FrameFormat::vtu, frame_topology(world, scene.bodies));
    for (int i = 0; i < 90; ++i) world.step();
    ASSERT_NE(world.time(), 1.5) << "the sum of 90 steps drifts";
    series.write(world, 90);
    const auto [pvd, time] = times_of(dir);
    EXPECT_NE(pvd.find("<DataSet timestep=\"1.5\" part=\"0\" file=\"r_00090.vtu\"/>"), std::string::npos) << pvd;
    EXPECT_EQ(time, std::vector<double>{1.5});
  }
  const test::TempDir dir("pbd_frame_series");
  for (double bad : {0.0, -0.01, std::nan(""), std::numeric_limits<double>::infinity()})
    test::expect_words(test::error_of([&] { FrameSeries(dir.path(), "r", FrameFormat::vtu, {}, bad); }),
                       {"frame series \"r\"", "time step", "positive and finite"});
}

TEST(FrameSeries, ALongSeriesRewritesThePvdLessOftenAndFinishListsEveryFrame) {
  TwoBodies<double> s;
  const test::TempDir dir("pbd_frame_series");
  FrameSeries series(dir.path(), "two", FrameFormat::vtu, s.topology);
  const long frames = 2 * long(FrameSeries::kPvdEveryFrame) + 8;
  for (long step = 0; step < frames; ++step) {
    series.write(s.world, step);
    const std::size_t listed = count_of(text_of(series.pvd_file()), "<DataSet ");
    // Every frame while the series is short; later the list may lag (by at most a second of frames), never lose one.
    if (step < long(FrameSeries::kPvdEveryFrame)) EXPECT_EQ(listed, std::size_t(step + 1));
    else EXPECT_GE(listed, FrameSeries::kPvdEveryFrame);
    s.world.step();
  }
  series.finish();
  EXPECT_EQ(count_of(text_of(series.pvd_file()), "<DataSet "), std::size_t(frames));
  EXPECT_EQ(files_in(dir.path()), std::size_t(frames) + 1) << "the frames and the .pvd, no temporaries";
}

TEST(FrameSeries, AnUnwritableFolderIsAnErrorNamingTheFileAndLeavesNothing) {
  const TwoBodies<float> s;
  for (FrameFormat format : {FrameFormat::obj, FrameFormat::vtu}) {
    FrameSeries missing("/nonexistent-pbd-dir", "two", format, s.topology);
    test::expect_words(test::error_of([&] { missing.write(s.world, 0); }),
                       {std::string("/nonexistent-pbd-dir/two_00000.") + name(format), "cannot open for writing"});
    EXPECT_EQ(missing.frames_written(), 0u);
    EXPECT_FALSE(std::filesystem::exists("/nonexistent-pbd-dir"));
  }
  // A folder where the frame should go: the error names it, no .pvd lists a frame that is not there.
  const test::TempDir dir("pbd_frame_series");
  std::filesystem::create_directories(dir / "two_00000.vtu");
  FrameSeries taken(dir.path(), "two", FrameFormat::vtu, s.topology);
  test::expect_words(test::error_of([&] { taken.write(s.world, 0); }), {"two_00000.vtu", "it is a folder"});
  EXPECT_EQ(files_in(dir.path()), 1u) << "no .pvd and no temporary";
}

TEST(FrameSeries, AFailedWriteLeavesNoHalfFrameAndNoTemporary) {
  // A file size limit makes the write fail after 4 KiB (SIGXFSZ ignored: write() returns EFBIG instead).
  const Scene scene = parse_scene(R"({"name": "big", "dt": 0.01, "bodies": [
      {"type": "cloth", "resolution": 40, "stretch": {}}]})", "big.json");
  const World<double> world = build_world<double>(scene.world);
  const test::TempDir dir("pbd_frame_series");
  FrameSeries series(dir.path(), "big", FrameFormat::vtu, frame_topology(world, scene.bodies));
  std::string message;
  {
    const test::FileSizeLimit limit(4096);
    message = test::error_of([&] { series.write(world, 0); });
  }
  test::expect_words(message, {"big_00000.vtu", "write failed"});
  EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << "no frame, no .pvd, no temporary";
}

// A write that fails at any file of any frame (an injected fault after the content is written and before it is
// named: fault_injection.hpp) leaves no temporary and no frame of its own; once the series finishes, its .pvd lists
// exactly the frames on disk, and the world it wrote is unchanged.
TEST(FrameSeries, AFaultWhileWritingAnyFileLeavesOnlyCompleteListedFrames) {
  for (const FrameFormat format : {FrameFormat::vtu, FrameFormat::obj})
    for (int hit = 1; hit <= 6; ++hit) {
      SCOPED_TRACE(std::string(name(format)) + " hit " + std::to_string(hit));
      TwoBodies<double> s;
      const test::TempDir dir("pbd_frame_series");
      FrameSeries series(dir.path(), "two", format, s.topology);
      const World<double> before = s.world;
      detail::arm_fault(detail::FaultPhase::frame_write, hit % 2 ? detail::FaultKind::error : detail::FaultKind::bad_alloc, hit);
      int failed = 0;
      for (int step = 0; step < 3; ++step) {
        try {
          series.write(s.world, step);
        } catch (const Error&) {
          ++failed;
        } catch (const std::bad_alloc&) {
          ++failed;
        }
      }
      const bool fired = detail::disarm_fault();
      EXPECT_EQ(failed, fired ? 1 : 0);
      if (format == FrameFormat::vtu) {
        EXPECT_TRUE(fired) << "three frames and their .pvd are six files";
      }
      series.finish();
      EXPECT_TRUE(s.world.positions() == before.positions());
      std::size_t frames = 0;
      for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
        const std::string file = entry.path().filename().string();
        EXPECT_EQ(file.find(".tmp"), std::string::npos) << file;
        if (entry.path().extension() == ".pvd") continue;
        ++frames;
        if (format == FrameFormat::vtu) {
          EXPECT_NE(text_of(series.pvd_file()).find(file), std::string::npos) << file;
        }
      }
      if (format == FrameFormat::vtu) {
        EXPECT_EQ(count_of(text_of(series.pvd_file()), "<DataSet "), frames);
      }
      EXPECT_EQ(frames, fired && (format == FrameFormat::obj || hit % 2 == 1) ? 2u : 3u);
    }
}

// A state gone non-finite is never written: the error names the frame and the particle, and nothing is left.
TEST(FrameSeries, AFrameOfANonFiniteStateIsRefusedNamingTheParticle) {
  for (FrameFormat format : {FrameFormat::obj, FrameFormat::vtu})
    for (const bool position : {true, false}) {
      TwoBodies<float> s;
      const test::TempDir dir("pbd_frame_series");
      FrameSeries series(dir.path(), "two", format, s.topology);
      series.write(s.world, 0);
      (position ? s.world.positions() : s.world.velocities())(1, 5) = std::numeric_limits<float>::quiet_NaN();
      test::expect_words(test::error_of([&] { series.write(s.world, 1); }),
                         {std::string("two_00001.") + name(format), "particle 5",
                          position ? "non-finite position" : "non-finite velocity"});
      EXPECT_EQ(series.frames_written(), 1u);
      series.finish();
      EXPECT_FALSE(std::filesystem::exists(series.frame_file(1)));
      EXPECT_EQ(files_in(dir.path()), format == FrameFormat::vtu ? 2u : 1u) << "frame 0 (and the .pvd) only";
    }
}

// A FIFO (or a device) that took a frame's or the .pvd's name is refused by name and left as it is, never opened:
// opening a FIFO for writing waits for a reader. (The test holds a reader, so that a writer that opens it fails
// this test rather than hangs it.)
TEST(FrameSeries, AFifoNamedLikeAFrameOrThePvdIsRefusedWithoutOpeningIt) {
  const TwoBodies<float> s;
  for (FrameFormat format : {FrameFormat::obj, FrameFormat::vtu})
    for (const bool pvd : {false, true}) {
      if (pvd && format == FrameFormat::obj) continue;
      const test::TempDir dir("pbd_frame_series");
      FrameSeries series(dir.path(), "two", format, s.topology);
      const std::filesystem::path taken = pvd ? series.pvd_file() : series.frame_file(0);
      ASSERT_EQ(::mkfifo(taken.c_str(), 0666), 0);
      const int reader = ::open(taken.c_str(), O_RDONLY | O_NONBLOCK);
      ASSERT_GE(reader, 0);
      test::expect_words(test::error_of([&] {
                           series.write(s.world, 0);
                           series.finish();
                         }),
                         {taken.filename().string(), "not a regular file"});
      char byte;
      EXPECT_LE(::read(reader, &byte, 1), 0) << "nothing was written into the FIFO";
      ::close(reader);
      EXPECT_TRUE(std::filesystem::is_fifo(taken));
    }
}

// Temporaries "<file>.<pid>.<n>.tmp" of a process that no longer runs (a run killed by SIGKILL) are removed by the
// next series' prepare(); those of processes that run are kept, and so is everything else.
TEST(FrameSeries, PrepareRemovesTheTemporariesOfDeadProcessesOnly) {
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ASSERT_GT(dead, 0);
  ASSERT_EQ(::waitpid(dead, nullptr, 0), dead);
  const TwoBodies<float> s;
  const test::TempDir dir("pbd_frame_series");
  const std::string mine = std::to_string(::getpid()), gone = std::to_string(dead);
  for (const std::string& name : std::vector<std::string>{
           "two_00003.vtu." + gone + ".7.tmp", "two.pvd." + gone + ".0.tmp", "two_00003.vtu." + mine + ".7.tmp",
           "two_00004.obj.1.2.tmp", "other.obj." + gone + ".1.tmp", "two_00005.vtu", "two_00006.vtu.x.1.tmp"})
    std::ofstream(dir / name) << "partial";
  FrameSeries series(dir.path(), "two", FrameFormat::vtu, s.topology);
  series.prepare();
  for (const std::string& name : {"two_00003.vtu." + gone + ".7.tmp", "two.pvd." + gone + ".0.tmp"})
    EXPECT_FALSE(std::filesystem::exists(dir / name)) << name;
  for (const std::string& name : std::vector<std::string>{"two_00003.vtu." + mine + ".7.tmp", "two_00004.obj.1.2.tmp",
                                                          "other.obj." + gone + ".1.tmp", "two_00005.vtu",
                                                          "two_00006.vtu.x.1.tmp"})
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  EXPECT_EQ(files_in(dir.path()), 5u) << "and no probe file left";
}

// prepare() refuses a folder no file can be created in, before any frame: one that does not exist, /sys (sysfs:
// refused even to root).
TEST(FrameSeries, PrepareRefusesAFolderThatCannotHoldAFile) {
  const TwoBodies<float> s;
  const FrameSeries missing("/nonexistent-pbd-dir", "two", FrameFormat::vtu, s.topology);
  test::expect_words(test::error_of([&] { missing.prepare(); }),
                     {"/nonexistent-pbd-dir/two.probe.", "cannot open for writing"});
  if (!std::filesystem::is_directory("/sys/kernel")) return;
  const FrameSeries sysfs("/sys/kernel", "two", FrameFormat::obj, s.topology);
  test::expect_words(test::error_of([&] { sysfs.prepare(); }), {"/sys/kernel/two.probe.", "cannot"});
}

}  // namespace
}  // namespace pbd
