// OBJ frames: what write_obj_frame writes, read back (header, one object per body, every vertex, faces and lines
// 1-based); which stretch constraints frame_topology draws as lines, body by body; errors naming the file, and no
// half-written frame; a FIFO without a reader is an error, not a hang.
#include "error_checks.hpp"
#include "pbd/io/frame_writer.hpp"
#include "pbd/io/generators.hpp"
#include "file_size_limit.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pbd {
namespace {

// A 3×3 cloth with stretch (particles 0-8, on its triangles), a 4-particle rope with stretch (9-12, on none), and
// one stretch constraint from the cloth to the rope.
template <class Real> struct ClothAndRope {
  World<Real> world;
  std::vector<std::array<Index, 3>> triangles;
  ClothAndRope() {
    const Index set = world.add_constraint_set(Stiffness::pbd_k(1.0));
    ClothOptions cloth;
    cloth.resolution = 3;
    triangles = add_cloth(world, cloth, set).triangles;
    RopeOptions rope;
    rope.particles = 4;
    rope.origin = {0.25, -0.5, 2.0};
    add_rope(world, rope, set);
    world.add_stretch(4, 9, set);
  }
};

// The lines of a text file.
std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

template <class Real> class FrameWriterTest : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(FrameWriterTest, Precisions);

TYPED_TEST(FrameWriterTest, TopologyDrawsLinesOnlyForStretchConstraintsOffTheSurface) {
  const ClothAndRope<TypeParam> s;
  const FrameTopology t = frame_topology(s.world, s.triangles);
  ASSERT_EQ(t.bodies.size(), 1u) << "a world without a scene is one body";
  const FrameBody& b = t.bodies[0];
  EXPECT_EQ(b.name, "world");
  EXPECT_EQ(b.first_particle, 0u);
  EXPECT_EQ(b.num_particles, 13u);
  EXPECT_EQ(b.triangles, s.triangles);
  // The rope's three segments; not the cloth's 16 edges, nor the constraint from cloth particle 4 to the rope.
  EXPECT_EQ(b.lines, (std::vector<std::array<Index, 2>>{{9, 10}, {10, 11}, {11, 12}}));
  EXPECT_EQ(b.line_stretch, (std::vector<Index>{16, 17, 18})) << "the stretch constraint each line draws";
  // Without triangles every stretch constraint is a line.
  EXPECT_EQ(frame_topology(s.world, std::vector<std::array<Index, 3>>{}).bodies[0].lines.size(),
            s.world.template constraints<StretchConstraint<TypeParam>>().size());
}

TYPED_TEST(FrameWriterTest, TopologyOfBodiesGivesEachBodyItsTrianglesAndLines) {
  const ClothAndRope<TypeParam> s;
  const std::vector<SceneBody> bodies{{"cloth_0", 0, 9, s.triangles}, {"rope_1", 9, 4, {}}};
  const FrameTopology t = frame_topology(s.world, bodies);
  ASSERT_EQ(t.bodies.size(), 2u);
  EXPECT_EQ(t.bodies[0].name, "cloth_0");
  EXPECT_EQ(t.bodies[0].triangles, s.triangles);
  EXPECT_TRUE(t.bodies[0].lines.empty());
  EXPECT_EQ(t.bodies[1].name, "rope_1");
  EXPECT_EQ(t.bodies[1].first_particle, 9u);
  // The constraint from cloth particle 4 to rope particle 9 joins two bodies: drawn by neither.
  EXPECT_EQ(t.bodies[1].lines, (std::vector<std::array<Index, 2>>{{9, 10}, {10, 11}, {11, 12}}));
  test::expect_words(test::error_of([&] { frame_topology(s.world, std::vector<SceneBody>{{"cloth_0", 0, 9, s.triangles}}); }),
                     {"frame_topology", "bodies hold 9 particles", "13"});
  test::expect_words(test::error_of([&] { frame_topology(s.world, std::vector<SceneBody>{{"a", 0, 9, {}}, {"b", 10, 3, {}}}); }),
                     {"frame_topology", "body b starts at particle 10, expected 9"});
  test::expect_words(test::error_of([&] { frame_topology(s.world, std::vector<SceneBody>{{"a", 0, 9, {}}, {"b", 9, 4, {{9, 10, 3}}}}); }),
                     {"frame_topology", "body b", "triangle 0", "particle index 3", "[9, 13)"});
}

TYPED_TEST(FrameWriterTest, WritesTheHeaderEveryVertexAndOneBasedFacesAndLines) {
  ClothAndRope<TypeParam> s;
  for (int i = 0; i < 3; ++i) s.world.step();  // moved off the grid, and a time to report
  const test::TempDir dir("pbd_frame_writer");
  const auto file = dir / "frame.obj";
  const FrameTopology t = frame_topology(s.world, s.triangles);
  write_obj_frame(file, s.world, t);
  const std::vector<std::string> lines = lines_of(file);
  const Index n = s.world.num_particles();
  const FrameBody& b = t.bodies[0];
  ASSERT_EQ(lines.size(), 2 + n + b.triangles.size() + b.lines.size());
  char header[96];
  std::snprintf(header, sizeof header, "# pbd frame: t = %.6f s, %u particles", s.world.time(), n);
  EXPECT_EQ(lines[0], header);
  EXPECT_NE(lines[0].find("t = 0.05"), std::string::npos) << "3 steps of 1/60 s: " << lines[0];
  EXPECT_EQ(lines[1], "o world");
  const auto x = s.world.positions();
  for (Index i = 0; i < n; ++i) {
    std::istringstream v(lines[2 + i]);
    std::string tag;
    double p[3];
    ASSERT_TRUE(v >> tag >> p[0] >> p[1] >> p[2]) << lines[2 + i];
    EXPECT_EQ(tag, "v");
    for (int d = 0; d < 3; ++d)  // %.7g: 7 significant digits
      EXPECT_NEAR(p[d], double(x(d, i)), 1e-6 * std::max(1.0, std::abs(double(x(d, i))))) << "vertex " << i;
  }
  for (std::size_t k = 0; k < b.triangles.size(); ++k) {
    const auto& tri = b.triangles[k];
    EXPECT_EQ(lines[2 + n + k], "f " + std::to_string(tri[0] + 1) + " " + std::to_string(tri[1] + 1) + " " +
                                    std::to_string(tri[2] + 1));
  }
  for (std::size_t k = 0; k < b.lines.size(); ++k)
    EXPECT_EQ(lines[2 + n + b.triangles.size() + k],
              "l " + std::to_string(b.lines[k][0] + 1) + " " + std::to_string(b.lines[k][1] + 1));
  EXPECT_EQ(lines.back(), "l 12 13");
  // Only the frame is left in the folder (the temporary it was written under is gone).
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()), 1);
}

TYPED_TEST(FrameWriterTest, AFrameIsReplacedWhole) {
  ClothAndRope<TypeParam> s;
  const test::TempDir dir("pbd_frame_writer");
  const auto file = dir / "frame.obj";
  std::ofstream(file) << std::string(100000, 'x') << "\n";  // longer than the frame: nothing of it may remain
  write_obj_frame(file, s.world, frame_topology(s.world, s.triangles));
  for (const std::string& line : lines_of(file)) EXPECT_NE(line[0], 'x');
}

TEST(FrameWriter, AnUnwritablePathIsAnErrorNamingTheFile) {
  const ClothAndRope<float> s;
  const FrameTopology t = frame_topology(s.world, s.triangles);
  test::expect_words(test::error_of([&] { write_obj_frame("/nonexistent-pbd-dir/f_00001.obj", s.world, t); }),
                     {"/nonexistent-pbd-dir/f_00001.obj", "cannot open for writing"});
  const test::TempDir dir("pbd_frame_writer");
  std::filesystem::create_directories(dir / "taken.obj");  // a folder where the frame should go
  test::expect_words(test::error_of([&] { write_obj_frame(dir / "taken.obj", s.world, t); }),
                     {"taken.obj", "it is a folder"});
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()), 1)
      << "the temporary is removed";
}

// A file the caller named that is a FIFO gets the bytes straight, but only with a reader: without one, opening it
// would wait forever; it is an error naming it instead.
TEST(FrameWriter, AFifoWithoutAReaderIsAnErrorNotAHang) {
  const ClothAndRope<float> s;
  const test::TempDir dir("pbd_frame_writer");
  const auto fifo = dir / "f.obj";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  test::expect_words(test::error_of([&] { write_obj_frame(fifo, s.world, frame_topology(s.world, s.triangles)); }),
                     {"f.obj", "FIFO that no process reads"});
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
}

TEST(FrameWriter, AFailedWriteLeavesNoFile) {
  // A file size limit makes the write fail after the first 4 KiB (SIGXFSZ ignored: write() returns EFBIG instead).
  ClothAndRope<double> s;
  ClothOptions big;
  big.resolution = 60;
  add_cloth(s.world, big, std::nullopt);
  const test::TempDir dir("pbd_frame_writer");
  const auto file = dir / "big.obj";
  std::string message;
  {
    const test::FileSizeLimit limit(4096);
    message = test::error_of([&] { write_obj_frame(file, s.world, frame_topology(s.world, s.triangles)); });
  }
  test::expect_words(message, {"big.obj", "write failed"});
  EXPECT_FALSE(std::filesystem::exists(file));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << "the temporary is removed";
}

TEST(FrameWriter, IndicesOutOfRangeAreErrorsAndWriteNothing) {
  const ClothAndRope<float> s;
  test::expect_words(test::error_of([&] { frame_topology(s.world, std::vector<std::array<Index, 3>>{{0, 1, 13}}); }),
                     {"frame_topology", "triangle 0", "particle index 13", "13 particles"});
  const test::TempDir dir("pbd_frame_writer");
  FrameTopology t;
  t.bodies = {{"all", 0, 13, {}, {{0, 1}, {12, 99}}, {0, 1}, {}, {}, {}, {}, {}}};
  test::expect_words(test::error_of([&] { write_obj_frame(dir / "f.obj", s.world, t); }),
                     {"f.obj", "body all", "line 1", "particle index 99"});
  t.bodies = {{"some", 0, 12, {}, {}, {}, {}, {}, {}, {}, {}}};
  test::expect_words(test::error_of([&] { write_obj_frame(dir / "f.obj", s.world, t); }),
                     {"f.obj", "bodies hold 12 particles", "13"});
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace pbd
