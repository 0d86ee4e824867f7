// load_obj reads its own numbers: every coordinate must still be the float tinyobjloader (which loaded the meshes
// before) gives it, bit for bit, and every face the same triangles.
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/obj_loader.hpp"
#include "tinyobj_reference.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace pbd {
namespace {

// An OBJ whose vertices have the given coordinates (three per vertex), each three vertices a triangle.
std::string obj_of(const std::vector<std::string>& coordinates) {
  std::string text = "# coordinates\n";
  for (std::size_t i = 0; i + 2 < coordinates.size(); i += 3)
    text += "v " + coordinates[i] + " " + coordinates[i + 1] + "\t" + coordinates[i + 2] + "\n";
  for (std::size_t i = 0; i + 2 < coordinates.size() / 3; i += 3) {
    text += "f ";
    text += std::to_string(i + 1);
    text += ' ';
    text += std::to_string(i + 2);
    text += ' ';
    text += std::to_string(i + 3);
    text += '\n';
  }
  return text;
}

void expect_same_as_tinyobj(const std::string& text) {
  const TriangleMesh ours = parse_obj(text, "t.obj");
  const auto reference = test::tinyobj_mesh(text);
  ASSERT_TRUE(reference.has_value());
  ASSERT_EQ(ours.num_vertices(), reference->num_vertices());
  for (Index i = 0; i < ours.num_vertices(); ++i)
    for (int d = 0; d < 3; ++d)
      ASSERT_EQ(std::memcmp(&ours.positions(d, i), &reference->positions(d, i), sizeof(double)), 0)
          << "vertex " << i << " coordinate " << d << ": " << ours.positions(d, i) << " vs " << reference->positions(d, i);
  EXPECT_EQ(ours.triangles, reference->triangles);
}

TEST(ObjReference, HandPickedNumbersReadAsTinyObjLoaderReadsThem) {
  expect_same_as_tinyobj(obj_of({"0", "-0", "+0", "1", "-1", "+1.5", ".5", "-.25", "5.", "1e2", "1E-2", "-0e0",
                                 "0.1", "0.7", "0.3", "3.14159265358979323846", "2.718281828459045235360287",
                                 "123456789012345678901234567890", "0.000000000000000000000000000001", "1e-45",
                                 "1.4e-45", "7e-46", "3.4028234e38", "3.40282346e+38", "-3.40282346e38",
                                 "0.123456789", "0.1234567891234567", "99999999999999999999", "1.5e-30", "1e30",
                                 "0.000012345", "1.00000011920928955078125", "16777217", "0.30000001192092896",
                                 "1e-5", "1.17549435e-38", "1e-400", "12345.6789e-3", "00000000000012.5", "2", "3"}));
}

TEST(ObjReference, RandomNumbersReadAsTinyObjLoaderReadsThem) {
  std::mt19937 rng(5);
  std::vector<std::string> coordinates;
  for (int i = 0; i < 30000; ++i) {
    std::string s = rng() % 2 ? "-" : "";
    const int whole = int(rng() % 12), fraction = int(rng() % 22);
    for (int k = 0; k < whole; ++k) s += char('0' + rng() % 10);
    if (whole == 0 || fraction > 0) s += ".";
    for (int k = 0; k < std::max(fraction, whole == 0 ? 1 : 0); ++k) s += char('0' + rng() % 10);
    if (rng() % 3 == 0) {
      s += 'e';
      s += std::to_string(int(rng() % 60) - 35);  // at most 11 digits × 10^24: in float range
    }
    coordinates.push_back(s);
  }
  coordinates.resize(coordinates.size() / 3 * 3);
  expect_same_as_tinyobj(obj_of(coordinates));
}

TEST(ObjReference, AWrittenIcosphereAndPolygonsReadAsTinyObjLoaderReadsThem) {
  const TriangleMesh m = icosphere_mesh(3, 1.7);
  std::string text;
  char line[128];
  for (Index i = 0; i < m.num_vertices(); ++i) {
    std::snprintf(line, sizeof line, "v %.9g %.17g %.6e\n", m.positions(0, i), m.positions(1, i), m.positions(2, i));
    text += line;
  }
  for (const auto& t : m.triangles) text += "f " + std::to_string(t[0] + 1) + "/1 " + std::to_string(t[1] + 1) + "//2 " +
                                            std::to_string(t[2] + 1) + "/3/4\r\n";
  text += "vn 0 0 1\nf -1 -2 -3 -4 -5\ng group\nf 1 2 3 4\n";
  expect_same_as_tinyobj(text);
}

}  // namespace
}  // namespace pbd
