// A body's "tethers" key (pbd/tethers.hpp): what it makes on cloth, rope and mesh bodies, the same tethers as
// World::add_tethers, the listed form under its own key, and errors naming the key.
#include "error_checks.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"

#include <gtest/gtest.h>

#include <numeric>
#include <string>

namespace pbd {
namespace {

using Tether = TetherConstraint<double>;

std::string cloth_scene(const std::string& tethers, const std::string& pin = "corners") {
  return R"({"name": "t", "dt": 0.01, "bodies": [{"type": "cloth", "resolution": 6, "pin": ")" + pin +
         R"(", "stretch": {"stiffness": 1.0})" + (tethers.empty() ? "" : ", \"tethers\": " + tethers) + "}]}";
}

std::size_t tethers_of(const std::string& text) {
  return parse_scene(text, "t.json").world.constraints<Tether>().size();
}

TEST(TetherKeys, TrueTethersEveryMovableParticleToItsNearestPin) {
  const Scene s = parse_scene(cloth_scene("true"), "t.json");
  const auto& t = s.world.constraints<Tether>();
  ASSERT_EQ(t.size(), 34u);  // 36 particles, 2 pinned
  EXPECT_EQ(s.world.sets.back().mode, StiffnessMode::xpbd);
  EXPECT_EQ(s.world.sets.back().compliance, 0.0);
  // The scene's tethers are World::add_tethers' on the same cloth.
  World<double> w = build_world<double>(parse_scene(cloth_scene(""), "t.json").world);
  std::vector<Index> body(36);
  std::iota(body.begin(), body.end(), Index(0));
  ASSERT_EQ(w.add_tethers(body), 34u);
  for (std::size_t k = 0; k < t.size(); ++k) {
    const Tether& a = t[k];
    const Tether& b = w.constraints<Tether>()[Index(k)];
    EXPECT_EQ(a.particles, b.particles);
    EXPECT_EQ(a.pin, b.pin);
    EXPECT_EQ(a.target, b.target);
    EXPECT_EQ(a.length, b.length);
  }
  // The pin survives the description: a world built from the scene follows its pins.
  EXPECT_EQ(build_world<float>(s.world).constraints<TetherConstraint<float>>()[0].pin, t[0].pin);
}

TEST(TetherKeys, OptionsFalseAndBodiesWithoutPins) {
  EXPECT_EQ(tethers_of(cloth_scene(R"({"to": "all", "length": "geodesic", "compliance": 1e-6})")), 68u);
  EXPECT_EQ(parse_scene(cloth_scene(R"({"compliance": 1e-6})"), "t.json").world.sets.back().compliance, 1e-6);
  EXPECT_EQ(tethers_of(cloth_scene("false")), 0u);
  EXPECT_EQ(tethers_of(cloth_scene("true", "none")), 0u);  // nothing to hang from: no tethers, no error
  EXPECT_EQ(tethers_of(cloth_scene("true", "edge")), 30u);
  const std::string rope = R"({"name": "r", "dt": 0.01, "bodies": [{"type": "rope", "particles": 5,
      "stretch": {"stiffness": 1.0}, "tethers": {"length": "geodesic"}}]})";
  const Scene r = parse_scene(rope, "r.json");
  const auto& t = r.world.constraints<Tether>();
  ASSERT_EQ(t.size(), 4u);
  EXPECT_NEAR(t[3].length, 1.0, 1e-15);  // the rope's length: the sum of its four edges
}

TEST(TetherKeys, TheListedFormHasItsOwnKey) {
  const std::string text = R"({"name": "l", "dt": 0.01, "bodies": [{"type": "particles", "positions": [[0, 0, 1]],
      "mass": 1.0, "tether_list": {"particles": [0], "target": [0, 0, 2], "length": 0.5}}]})";
  const Scene l = parse_scene(text, "l.json");
  const auto& t = l.world.constraints<Tether>();
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].target, Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(t[0].length, 0.5);
  EXPECT_EQ(t[0].pin, Tether::kNoPin);
}

TEST(TetherKeys, ErrorsNameTheKey) {
  auto error = [](const std::string& text) { return test::error_of([&] { parse_scene(text, "bad.json"); }); };
  test::expect_words(error(cloth_scene(R"({"to": "far"})")),
                     {"bad.json", "/bodies/0/tethers/to", "expected \"nearest\" or \"all\"", "\"far\""});
  test::expect_words(error(cloth_scene(R"({"length": "straight"})")),
                     {"/bodies/0/tethers/length", "expected \"euclidean\" or \"geodesic\""});
  test::expect_words(error(cloth_scene(R"({"compliance": -1})")), {"/bodies/0/tethers/compliance"});
  test::expect_words(error(cloth_scene(R"({"nearest": true})")), {"/bodies/0/tethers", "nearest"});
  test::expect_words(error(cloth_scene("3")), {"/bodies/0/tethers", "expected true, false or an object"});
  test::expect_words(error(R"({"name": "p", "dt": 0.01, "bodies": [{"type": "particles", "positions": [[0, 0, 1]],
      "mass": 1.0, "tethers": true}]})"), {"/bodies/0/tethers", "cloth, rope and mesh bodies", "\"particles\""});
}

}  // namespace
}  // namespace pbd
