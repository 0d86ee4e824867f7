// Bad input to the two file formats pbd reads, scenes (JSON) and meshes (OBJ): malformed, truncated, oversized,
// inconsistent or non-finite data is a pbd::Error naming the file, the key (scenes, as a JSON Pointer) or the line
// (OBJ), and what is wrong; never a crash, another exception, a hang or a huge allocation. The basic cases (unknown
// keys, wrong types, out-of-range values; bad indices and numbers in OBJ) are in scene_test.cpp and mesh_test.cpp;
// the inputs tests/fuzz found are kept here as regression cases.
#include "error_checks.hpp"
#include "temp_dir.hpp"
#include "pbd/io/obj_loader.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/io/tet_mesh_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

namespace pbd {
namespace {

using test::error_of;
using test::expect_words;
using test::replaced;

void expect_scene_error(const std::string& text, std::initializer_list<std::string> words) {
  expect_words(error_of([&] { parse_scene(text, "bad.json"); }), words);
}

void expect_obj_error(const std::string& text, std::initializer_list<std::string> words) {
  expect_words(error_of([&] { parse_obj(text, "bad.obj"); }), words);
}

const std::string kScene = R"({"name": "t", "dt": 0.01, "description": "d",
  "bodies": [
    {"type": "particles", "positions": [[0,0,0],[1,0,0]], "velocities": [[0,0,0],[0,1,0]],
     "stretch": {"pairs": [[0,1]], "stiffness": 1}},
    {"type": "rope", "particles": 3, "direction": [1, 0, 0]}
  ],
  "colliders": [{"type": "plane", "normal": [0, 0, 1], "offset": 0}]
})";

const std::string kTetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

TEST(BadInputScene, TheReferenceScenesLoad) {
  EXPECT_EQ(parse_scene(kScene, "ok.json").world.num_particles(), 5u);
  EXPECT_EQ(parse_obj(kTetra, "ok.obj").triangles.size(), 4u);
}

// --- scenes: malformed, truncated, binary ----------------------------------------------------------------------

TEST(BadInputScene, SweepOrderIsForwardOrSymmetric) {
  EXPECT_EQ(parse_scene(kScene, "ok.json").world.params.sweep_order, SweepOrder::forward);  // the default
  const std::string symmetric = replaced(kScene, "\"description\": \"d\"", "\"description\": \"d\", \"sweep_order\": \"symmetric\"");
  EXPECT_EQ(parse_scene(symmetric, "ok.json").world.params.sweep_order, SweepOrder::symmetric);
  expect_scene_error(replaced(kScene, "\"description\": \"d\"", "\"description\": \"d\", \"sweep_order\": \"backward\""),
                     {"bad.json", "sweep_order", "unknown sweep order", "\"backward\"", "symmetric"});
  expect_scene_error(replaced(kScene, "\"description\": \"d\"", "\"description\": \"d\", \"sweep_order\": 1"),
                     {"bad.json", "sweep_order"});
}

TEST(BadInputScene, PrimaryErrorIsAKnownMeasure) {
  EXPECT_EQ(parse_scene(kScene, "ok.json").primary_error, "");  // not stated: the study picks
  const std::string stretch = replaced(kScene, "\"description\": \"d\"", "\"description\": \"d\", \"primary_error\": \"stretch\"");
  EXPECT_EQ(parse_scene(stretch, "ok.json").primary_error, "stretch");
  const std::string reference = replaced(kScene, "\"description\": \"d\"", "\"description\": \"d\", \"primary_error\": \"reference\"");
  EXPECT_EQ(parse_scene(reference, "ok.json").primary_error, "reference");  // the study's distance from its reference
  expect_scene_error(replaced(kScene, "\"description\": \"d\"", "\"description\": \"d\", \"primary_error\": \"energy\""),
                     {"bad.json", "primary_error", "unknown error measure", "\"energy\"", "penetration", "reference"});
  expect_scene_error(replaced(kScene, "\"description\": \"d\"", "\"description\": \"d\", \"primary_error\": 2"),
                     {"bad.json", "primary_error"});
}

TEST(BadInputScene, CutAnywhereIsAnErrorNamingTheFile) {
  for (std::size_t n = 0; n < kScene.size(); ++n) {
    const std::string message = error_of([&] { parse_scene(kScene.substr(0, n), "cut.json"); });
    ASSERT_EQ(message.rfind("cut.json: ", 0), 0u) << "cut at " << n << ": " << message;
    ASSERT_NE(message.find("line"), std::string::npos) << "cut at " << n << ": " << message;
  }
}

TEST(BadInputScene, BinaryGarbageAndBrokenTextNameTheLine) {
  expect_scene_error(std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16), {"bad.json", "parse error at line 1"});
  expect_scene_error(std::string("{\"name\": \"a\0b\"}", 15), {"parse error at line 1", "control character"});
  expect_scene_error("{\"name\": \"\xff\xfe\"}", {"parse error at line 1", "UTF-8"});
  expect_scene_error(kScene + "\n}", {"parse error at line 9"});                  // trailing garbage
  expect_scene_error(replaced(kScene, "\"d\",", "\"d\""), {"parse error at line 2"});  // a comma missing
  expect_scene_error("   \n\t\n", {"parse error at line 3"});
}

// --- scenes: non-finite and out-of-range numbers ----------------------------------------------------------------

TEST(BadInputScene, NumbersBeyondDoubleAreParseErrorsNotCrashes) {
  // nlohmann::json reports these as out_of_range, which used to escape parse_scene (found by tests/fuzz).
  // Such a number also names its key (the lexer read it where a value was due).
  expect_scene_error(replaced(kScene, "0.01", "1e400"), {"bad.json: /dt: ", "line 1, column", "1e400"});
  expect_scene_error(replaced(kScene, "[1, 0, 0]", "[1, -1e400, 0]"), {"/bodies/1/direction/1: ", "line 5", "-1e400"});
  expect_scene_error("1e400", {"bad.json: parse error at line 1", "1e400"});  // the root: no key to name
  expect_scene_error(replaced(kScene, "0.01", "NaN"), {"parse error at line 1"});
  expect_scene_error(replaced(kScene, "0.01", "Infinity"), {"parse error at line 1"});
  expect_scene_error(replaced(kScene, "0.01", "1e308"), {"/dt", "beyond the range of float"});
  expect_scene_error(replaced(kScene, "\"particles\": 3", "\"particles\": 99999999999999999999"),
                     {"/bodies/1/particles", "expected an integer"});
  expect_scene_error(replaced(kScene, "\"particles\": 3", "\"particles\": 18446744073709551615"),
                     {"/bodies/1/particles", "out of range"});
  expect_scene_error(replaced(kScene, "\"particles\": 3", "\"particles\": -9223372036854775808"),
                     {"/bodies/1/particles", "out of range"});
}

TEST(BadInputScene, VectorsWhoseLengthOverflowsOrVanishes) {
  expect_scene_error(replaced(kScene, "[1, 0, 0]", "[1e300, 1e300, 0]"), {"/bodies/1/direction/0", "range of float"});
  expect_scene_error(replaced(kScene, "[1, 0, 0]", "[1e-200, 0, 0]"), {"/bodies/1/direction", "zero"});
  expect_scene_error(replaced(kScene, "[0, 0, 1]", "[1e200, 0, 1e200]"), {"/colliders/0/normal/0", "range of float"});
  EXPECT_NO_THROW(parse_scene(replaced(kScene, "\"offset\": 0", "\"offset\": -1e18"), "ok.json"));
  // a contact squares the offset: in float's range, but not its square (issue 48)
  expect_scene_error(replaced(kScene, "\"offset\": 0", "\"offset\": -3e38"), {"/colliders/0/offset", "at most"});
  // offset × |normal| (the offset is along the normal as given) leaves float's range with a long normal
  expect_scene_error(replaced(replaced(kScene, "\"offset\": 0", "\"offset\": 3e38"), "[0, 0, 1]", "[0, 0, 10]"),
                     {"/colliders/0/offset", "beyond the range of float"});
}

TEST(BadInputScene, EveryValueFitsFloatSoTheErrorNamesTheKeyNotAConversion) {
  // A gravity of 1e308 is finite in double; it used to fail only in build_world<float>, naming neither file nor key.
  expect_scene_error(replaced(kScene, "\"dt\": 0.01", "\"dt\": 0.01, \"gravity\": [0, 0, 1e308]"),
                     {"bad.json: /gravity/2: ", "1e+308", "beyond the range of float"});
  expect_scene_error(replaced(kScene, "[1,0,0]", "[1,-4e38,0]"), {"bad.json: /bodies/0/positions/1/1: ", "float"});
  expect_scene_error(replaced(kScene, "[0,1,0]", "[0,1e39,0]"), {"bad.json: /bodies/0/velocities/1/1: ", "float"});
  EXPECT_NO_THROW(parse_scene(replaced(kScene, "[1,0,0]", "[1,-3e38,0]"), "ok.json"));  // float's largest is 3.4e38
}

TEST(BadInputScene, TheNameIsAPlainFileNameNotAPath) {
  // It names the frames `pbd run --frames DIR` writes: "../../x" used to put them two folders above DIR.
  for (const char* name : {"../../x", "a/b", "/etc/x", "a\\\\b", "..", ".", ""})
    expect_scene_error(replaced(kScene, "\"name\": \"t\"", std::string("\"name\": \"") + name + "\""),
                       {"bad.json: /name: ", "plain file name"});
  expect_scene_error(replaced(kScene, "\"name\": \"t\"", "\"name\": \"" + std::string(101, 'x') + "\""),
                     {"/name", "at most 100 bytes"});
  EXPECT_EQ(parse_scene(replaced(kScene, "\"name\": \"t\"", "\"name\": \"cloth-fold_2.v1\""), "ok.json").name,
            "cloth-fold_2.v1");
}

TEST(BadInputScene, StringsHoldNoControlOrBidirectionalCharacters) {
  // U+202E (right-to-left override) made "x\u202Egpj.json" show as "xnosj.jpg"; every string key is checked alike.
  for (const char* c : {"\\u202e", "\\u0001", "\\u0085", "\\u200b", "\\u2066", "\\ufeff", "\\u2028"}) {
    const std::string in = std::string("a") + c + "b";
    expect_scene_error(replaced(kScene, "\"name\": \"t\"", "\"name\": \"" + in + "\""),
                       {"bad.json: /name: ", "control or format character"});
    expect_scene_error(replaced(kScene, "\"description\": \"d\"", "\"description\": \"" + in + "\""),
                       {"bad.json: /description: ", "control or format character"});
    expect_scene_error(replaced(kScene, "\"rope\"", "\"" + in + "\""), {"/bodies/1/type", "control or format"});
    expect_scene_error(replaced(kScene, "\"description\": \"d\"", "\"description\": \"d\", \"primary_error\": \"" + in + "\""),
                       {"/primary_error", "control or format"});
  }
  // The message shows the character escaped, never the character itself (it would reorder the message).
  const std::string message = error_of([&] { parse_scene(replaced(kScene, "\"name\": \"t\"", "\"name\": \"x\\u202egpj.json\""), "b.json"); });
  expect_words(message, {"U+202E", "\"x\\u202egpj.json\""});
  EXPECT_EQ(message.find("\u202e"), std::string::npos) << message;
  EXPECT_EQ(parse_scene(replaced(kScene, "\"name\": \"t\"", "\"name\": \"caf\u00e9 \u4e2d\""), "ok.json").name,
            "caf\u00e9 \u4e2d");  // other characters stay allowed
  expect_scene_error(replaced(kScene, "\"name\": \"t\"", "\"name\": \"a\\u0000b\""), {"/name", "U+0000", "a\\x00b"});
}

// Every message is valid UTF-8, whatever bytes the file holds (Python decodes it as such: a byte of no valid
// sequence used to leave pbd.Error without any message).
bool valid_utf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    const std::size_t n = b < 0x80 ? 1 : (b >> 5) == 6 ? 2 : (b >> 4) == 14 ? 3 : (b >> 3) == 30 ? 4 : 0;
    if (n == 0 || i + n > s.size()) return false;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
    i += n;
  }
  return true;
}

TEST(BadInputScene, MessagesAreValidUtf8WhateverBytesTheFileHolds) {
  // A scene typed with smart quotes saved as cp1252: 0x93 and 0x94 where the quotes belong.
  const std::string cp1252 = replaced(kScene, "\"name\": \"t\"", "\"name\": \x93t\x94");
  std::string message = error_of([&] { parse_scene(cp1252, "smart\xff.json"); });
  expect_words(message, {"smart\\xff.json: ", "line 1, column", "\\x93"});
  EXPECT_TRUE(valid_utf8(message)) << message;
  for (const char* bytes : {"\xc3", "\xe2\x80", "\xed\xa0\x80", "\xc0\xaf", "\xf8\x88\x80\x80\x80", "\xff\xfe"}) {
    message = error_of([&] { parse_scene(replaced(kScene, "\"name\": \"t\"", std::string("\"name\": ") + bytes), "b.json"); });
    EXPECT_TRUE(valid_utf8(message)) << message;
    expect_words(message, {"b.json: parse error at line 1"});
  }
}

TEST(BadInputScene, ANulByteIsRefusedWhereverItIsNotTakenForTheEnd) {
  // nlohmann's lexer ends the text at a NUL byte: valid JSON, then "\0garbage", used to load.
  expect_scene_error(kScene + std::string("\0garbage", 8), {"bad.json: parse error at line 8, column 2", "NUL byte"});
  expect_scene_error(kScene + std::string("\n\0", 2), {"parse error at line 9, column 1", "NUL byte"});
  expect_scene_error(replaced(kScene, "\"d\",", std::string("\"d\",\0", 5)), {"line 1, column", "NUL byte"});
  expect_scene_error(kScene + "\n{}", {"parse error at line 9"});  // trailing content without a NUL, as before
}

TEST(BadInputScene, SelfCollisionNeedsARadius) {
  // docs/scenes.md: self_collision needs a radius (points never touch); so does nothing else in "contact".
  const std::string rope = "\"direction\": [1, 0, 0]";
  expect_scene_error(replaced(kScene, rope, rope + ", \"contact\": {\"self_collision\": true}"),
                     {"bad.json: /bodies/1/contact/self_collision: ", "radius"});
  expect_scene_error(replaced(kScene, rope, rope + ", \"contact\": {\"radius\": 0, \"self_collision\": true}"),
                     {"/bodies/1/contact/self_collision", "radius"});
  EXPECT_NO_THROW(parse_scene(replaced(kScene, rope, rope + ", \"contact\": {\"radius\": 0.1, \"self_collision\": true}"), "ok.json"));
  EXPECT_NO_THROW(parse_scene(replaced(kScene, rope, rope + ", \"contact\": {\"self_collision\": false}"), "ok.json"));
}

TEST(BadInputScene, PrimaryErrorNeedsWhatItMeasuresInTheScene) {
  // pbd study refused these and pbd run took them; the parser refuses them now, for every command.
  auto with = [](const std::string& scene, const std::string& measure) {
    return replaced(scene, "\"description\": \"d\"", "\"description\": \"d\", \"primary_error\": \"" + measure + "\"");
  };
  expect_scene_error(with(kScene, "bending"), {"bad.json: /primary_error: the scene has no bending constraint to measure"});
  expect_scene_error(with(kScene, "volume"), {"/primary_error: the scene has no volume constraint to measure"});
  expect_scene_error(with(kScene, "overlap"), {"/primary_error: the scene has no contact body with a radius to measure"});
  const std::string no_collider = replaced(kScene, "\"colliders\": [{\"type\": \"plane\", \"normal\": [0, 0, 1], \"offset\": 0}]", "\"colliders\": []");
  expect_scene_error(with(no_collider, "penetration"), {"/primary_error: the scene has no collider to measure"});
  for (const char* measure : {"stretch", "penetration", "reference"})
    EXPECT_EQ(parse_scene(with(kScene, measure), "ok.json").primary_error, measure);
  const std::string radius = replaced(kScene, "\"direction\": [1, 0, 0]", "\"direction\": [1, 0, 0], \"contact\": {\"radius\": 0.1}");
  EXPECT_EQ(parse_scene(with(radius, "overlap"), "ok.json").primary_error, "overlap");
}

TEST(BadInputScene, MassesWhoseInverseFloatCannotHoldAreRefusedNotPinned) {
  // A grip's mass may be up to float's largest, 3.4e38; in float its inverse is then subnormal, and a
  // heavier one would round to 0 and pin the particle without a word.
  const std::string rope = "\"direction\": [1, 0, 0]";
  auto grip = [&](const char* mass) {
    return replaced(kScene, rope, rope + ", \"grips\": [{\"particles\": [2], \"mass\": " + mass + "}]");
  };
  expect_scene_error(grip("3e38"), {"bad.json: /bodies/1: particle 2 of rope_1", "not a normal float"});
  expect_scene_error(grip("1e38"), {"/bodies/1: particle 2", "not a normal float"});
  EXPECT_NO_THROW(parse_scene(grip("1e37"), "ok.json"));
  // the tet body's masses come from its density and volume
  const std::string tets = R"({"name": "t", "dt": 0.01, "bodies": [{"type": "tets", "scale": 1e9, "density": 1e9,
    "generator": {"type": "box", "cells": [1, 1, 1], "size": [1000, 1000, 1000]}, "tet_volume": {}}]})";
  expect_scene_error(tets, {"/bodies/0: particle 0 of tets_0", "not a normal float"});
}

TEST(BadInputScene, ValuesWhoseStepOverflowsFloatAreRefusedAtLoadNamingTheKey) {
  // In float's range, but the step squares a speed and divides a compliance by the sub-step squared: these used to
  // end the run as "non-finite positions", naming nothing.
  expect_scene_error(replaced(kScene, "\"dt\": 0.01", "\"dt\": 0.01, \"gravity\": [0, 0, -3e38]"),
                     {"bad.json: /gravity: ", "float"});
  expect_scene_error(replaced(kScene, "[0,1,0]", "[0,3e38,0]"), {"bad.json: /bodies/0/velocities/1: ", "speed", "float"});
  expect_scene_error(replaced(kScene, "\"stiffness\": 1}", "\"compliance\": 3e38}"),
                     {"bad.json: /bodies/0/stretch/compliance: ", "sub-step", "float"});
  expect_scene_error(replaced(kScene, "\"offset\": 0}", "\"offset\": 0}, {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 3e38}"),
                     {"/colliders/1/radius", "out of range"});
  const std::string rope = "\"direction\": [1, 0, 0]";
  expect_scene_error(replaced(kScene, rope, rope + ", \"grips\": [{\"particles\": [2], \"velocity\": [1e20, 0, 0]}]"),
                     {"/bodies/1/grips/0/velocity", "speed"});
  expect_scene_error(replaced(kScene, rope, rope + ", \"tethers\": {\"compliance\": 1e38}"),
                     {"/bodies/1/tethers/compliance", "sub-step"});
  EXPECT_NO_THROW(parse_scene(replaced(kScene, "\"dt\": 0.01", "\"dt\": 0.01, \"gravity\": [0, 0, -1e15]"), "ok.json"));
}

TEST(BadInputScene, SubstepsAndIterationsAreBounded) {
  // 100,000 of each (10^10 sweeps a step) used to run with no progress and no end.
  auto with = [](const char* substeps, const char* iterations) {
    return replaced(kScene, "\"dt\": 0.01", std::string("\"dt\": 0.01, \"substeps\": ") + substeps + ", \"iterations\": " + iterations);
  };
  expect_scene_error(with("100000", "100000"), {"bad.json: /iterations: ", "10000000000 sweeps a step", "limit of 1000000"});
  expect_scene_error(with("100001", "1"), {"bad.json: /substeps: ", "out of range [1, 100000]"});
  expect_scene_error(with("1", "100001"), {"bad.json: /iterations: ", "out of range [0, 100000]"});
  expect_scene_error(with("100000", "11"), {"bad.json: /iterations: ", "1100000 sweeps a step"});
  EXPECT_EQ(parse_scene(replaced(kScene, "\"dt\": 0.01", "\"dt\": 0.01, \"substeps\": 100000"), "ok.json")
                .world.params.substeps, 100000);  // at the default 10 iterations: 10^6 sweeps, the limit
  EXPECT_EQ(parse_scene(with("1000", "1000"), "ok.json").world.params.substeps, 1000);
}

// --- scenes: oversized ------------------------------------------------------------------------------------------

TEST(BadInputScene, HugeGeneratorsAreRefusedBeforeAllocating) {
  const std::string tube = R"({"name": "t", "dt": 0.01, "bodies": [
    {"type": "mesh", "generator": {"type": "tube", "segments": 100000, "rings": 100000}}]})";
  // 10^10 vertices: used to overflow an int in tube_mesh and allocate gigabytes (found by tests/fuzz).
  expect_scene_error(tube, {"/bodies/0/generator/rings", "10000000000 particles", "limit of 50000000"});
  expect_scene_error(replaced(tube, "\"rings\": 100000", "\"rings\": 501"), {"/bodies/0/generator/rings", "limit"});
  expect_scene_error(replaced(kScene, "\"particles\": 3", "\"particles\": 50000001"), {"/bodies/1/particles", "range"});
  expect_scene_error(R"({"name": "t", "dt": 0.01, "bodies": [{"type": "cloth", "resolution": 1000000}]})",
                     {"/bodies/0/resolution", "out of range [2, 4096]"});
  expect_scene_error(R"({"name": "t", "dt": 0.01, "bodies": [
    {"type": "mesh", "generator": {"type": "grid", "resolution": 4097}}]})",
                     {"/bodies/0/generator/resolution", "out of range"});
}

TEST(BadInputScene, EveryBodyIsSizedBeforeAnyIsBuilt) {
  // Four 4096² cloths: 67 M particles. The first three fit the limit one by one and used to be built (31 s,
  // 3.4 GB) before the fourth was refused; now the sizes are added up from the keys before anything is built.
  const std::string cloth = R"({"type": "cloth", "resolution": 4096, "stretch": {}})";
  const std::string four = R"({"name": "t", "dt": 0.01, "bodies": [)" + cloth + "," + cloth + "," + cloth + "," +
                           cloth + "]}";
  expect_scene_error(four, {"bad.json: /bodies/2/resolution: ", "16777216 particles", "33554432 of the bodies before it",
                            "limit of 50000000 particles"});
  // Two cloths with every surface constraint: 33.5 M particles fit, 268 M constraints do not.
  const std::string full = R"({"type": "cloth", "resolution": 4096, "stretch": {}, "bending": {}, "area": {}})";
  expect_scene_error(R"({"name": "t", "dt": 0.01, "bodies": [)" + full + "," + full + "]}",
                     {"bad.json: /bodies/1/resolution: ", "constraints", "limit of 200000000 constraints"});
  const std::string spheres = R"({"type": "mesh", "generator": {"type": "icosphere", "level": 8}, "stretch": {}})";
  std::string many = R"({"name": "t", "dt": 0.01, "bodies": [)" + spheres;
  for (int i = 0; i < 99; ++i) many += "," + spheres;  // 100 × 655362 vertices
  expect_scene_error(many + "]}", {"/bodies/76/generator/level: ", "limit of 50000000 particles"});
}

TEST(BadInputScene, OversizedTextAndDeepNesting) {
  expect_scene_error(std::string((64u << 20) + 1, ' '), {"bad.json", "67108865 bytes", "more than"});
  std::string deep = std::string(100, '[') + std::string(100, ']');
  expect_scene_error(replaced(kScene, "\"d\"", deep), {"/description/0/0/0", "nested more than 64 deep"});
  // A million levels: no recursion anywhere (parse, error, destruction), so no stack overflow.
  deep = std::string(1'000'000, '[') + std::string(1'000'000, ']');
  expect_scene_error(replaced(kScene, "\"d\"", deep), {"/description/0", "nested more than 64 deep"});
  deep = std::string(1'000'000, '[');
  expect_scene_error(deep, {"/0/0", "nested more than 64 deep"});
}

TEST(BadInputScene, LongOrStrangeStringsAreShortenedInMessages) {
  const std::string long_word(1'000'000, 'x');
  expect_scene_error(replaced(kScene, "\"description\"", "\"" + long_word + "\""), {"unknown key", "/xxxx", "..."});
  expect_scene_error(replaced(kScene, "\"rope\"", "\"" + long_word + "\""), {"/bodies/1/type", "unknown body type"});
  expect_scene_error(replaced(kScene, "\"rope\"", "\"ro\\u0000pe\""), {"/bodies/1/type", "ro\\x00pe"});
  expect_scene_error(replaced(kScene, "\"description\"", "\"a/b~c\""), {"/a~1b~0c", "unknown key"});
  expect_scene_error(replaced(kScene, "0.01", "\"" + long_word + "\""), {"/dt", "expected a number", "..."});
  std::string many = "[1";
  for (int i = 0; i < 100'000; ++i) many += ",1";
  expect_scene_error(replaced(kScene, "0.01", many + "]"), {"/dt", "expected a number, got an array"});
}

// --- scenes: inconsistent ---------------------------------------------------------------------------------------

TEST(BadInputScene, KeysGivenTwiceAreErrorsNotSilentlyOverwritten) {
  expect_scene_error(replaced(kScene, "\"dt\": 0.01,", "\"dt\": 0.01, \"dt\": 5,"), {"bad.json: /dt", "twice"});
  expect_scene_error(replaced(kScene, "\"particles\": 3", "\"particles\": 3, \"particles\": 4"),
                     {"/bodies/1/particles", "twice"});
}

TEST(BadInputScene, CountsAndIndicesThatDoNotAgree) {
  expect_scene_error(replaced(kScene, "[[0,0,0],[0,1,0]]", "[[0,0,0]]"), {"/bodies/0/velocities", "1 entries for 2"});
  expect_scene_error(replaced(kScene, "[[0,1]]", "[[0,1,1]]"), {"/bodies/0/stretch/pairs/0", "pair"});
  expect_scene_error(replaced(kScene, "[[0,1]]", "[[0,-1]]"), {"/bodies/0/stretch/pairs/0/1", "out of range"});
  expect_scene_error(replaced(kScene, "[[0,0,0],[1,0,0]]", "[]"), {"/bodies/0/positions", "at least one"});
  expect_scene_error(replaced(kScene, "[[0,0,0],[1,0,0]]", "[[0,0,0],[1,0]]"), {"/bodies/0/positions/1", "3 numbers"});
  expect_scene_error(replaced(kScene, "\"direction\"", "\"anchors\": {\"particles\": [3]}, \"direction\""),
                     {"/bodies/1/anchors/particles/0", "out of range [0, 2]"});
}

// --- scenes: the OBJ files they name ----------------------------------------------------------------------------

class BadInputSceneMesh : public ::testing::Test {
protected:
  pbd::test::TempDir dir{"pbd_bad_input"};
  std::filesystem::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
  }
  // Loads a scene file whose one mesh body is {"type": "mesh", "obj": obj_name, "stretch": {}}.
  std::string scene_error(const std::string& obj_name) {
    const auto scene = write("scene.json", R"({"name": "m", "dt": 0.01, "bodies": [{"type": "mesh", "obj": ")" +
                                               obj_name + R"(", "stretch": {}}]})");
    return error_of([&] { load_scene(scene); });
  }
};

TEST_F(BadInputSceneMesh, TheErrorNamesTheSceneTheKeyTheMeshAndItsLine) {
  write("tetra.obj", kTetra);
  EXPECT_NO_THROW(load_scene(write("ok.json", R"({"name": "m", "dt": 0.01, "bodies": [
    {"type": "mesh", "obj": "tetra.obj", "volume": {}}]})")));
  write("broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n");
  expect_words(scene_error("broken.obj"), {"scene.json: /bodies/0/obj: ", "broken.obj:3: ", "\"nan\""});
  write("empty.obj", "");
  expect_words(scene_error("empty.obj"), {"scene.json: /bodies/0/obj: ", "empty.obj", "empty (0 bytes)"});
  expect_words(scene_error("missing.obj"), {"scene.json: /bodies/0/obj: ", "missing.obj", "cannot read"});
  std::filesystem::create_directories(dir / "folder.obj");
  expect_words(scene_error("folder.obj"), {"/bodies/0/obj: ", "folder.obj", "not a regular file"});
  expect_words(scene_error(""), {"/bodies/0/obj", "file name is empty"});
  expect_words(scene_error("tetra.obj\\u0000.png"), {"/bodies/0/obj", "U+0000", "tetra.obj\\x00.png"});
  write("twice.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1\n");  // would give stretch (0, 0)
  expect_words(scene_error("twice.obj"), {"/bodies/0/obj: ", "twice.obj:4: ", "vertex 1 twice"});
}

TEST_F(BadInputSceneMesh, VolumeErrorsNameTheObjFileAndItsOneBasedVertices) {
  write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n");  // face 1 4 3 missing
  const auto open = write("open.json", R"({"name": "m", "dt": 0.01, "bodies": [
    {"type": "mesh", "obj": "open.obj", "volume": {}}]})");
  expect_words(error_of([&] { load_scene(open); }),
               {"open.json: /bodies/0/obj: ", "open.obj: ", "edge (1, 3) belongs to one triangle only",
                "vertex numbers as in the file, from 1"});
  write("inside_out.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n");
  const auto inside_out = write("inside_out.json", R"({"name": "m", "dt": 0.01, "bodies": [
    {"type": "mesh", "obj": "inside_out.obj", "volume": {}}]})");
  expect_words(error_of([&] { load_scene(inside_out); }),
               {"inside_out.json: /bodies/0/obj: ", "inside_out.obj: ", "inside out"});
}

TEST_F(BadInputSceneMesh, SpecialFilesAreNotRead) {
  // A device or a /proc file has no size to check; reading it could block or never end.
  expect_words(scene_error("/dev/zero"), {"/bodies/0/obj: ", "not a regular file"});
  expect_words(scene_error("/proc/self/status"), {"/bodies/0/obj: ", "empty (0 bytes)"});
}

// --- OBJ: empty, binary, truncated --------------------------------------------------------------------------

TEST(BadInputTetMesh, ANulByteIsRefusedInEveryTextFormatEvenInACommentOrAnUnreadSection) {
  const std::string node = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", ele = "1 4 0\n1 1 2 3 4\n";
  EXPECT_EQ(parse_tetgen(node, "t.node", ele, "t.ele").tets.size(), 1u);
  const std::string nul("\0", 1);
  expect_words(error_of([&] { parse_tetgen(node + "# x" + nul + "y\n", "t.node", ele, "t.ele"); }),
               {"t.node:6: a NUL byte at column 4"});
  expect_words(error_of([&] { parse_tetgen(node, "t.node", "1 4 0\n1 1 2 3 4" + nul + "\n", "t.ele"); }),
               {"t.ele:2: a NUL byte at column 10"});
  const std::string msh = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                          "$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n";
  EXPECT_EQ(parse_gmsh(msh, "t.msh").tets.size(), 1u);
  expect_words(error_of([&] { parse_gmsh(msh + "$NodeData\n" + nul + "\n", "t.msh"); }),
               {"t.msh:16: a NUL byte at column 1"});
  // OBJ: refused as a byte that is not text (BadInputObj.BinaryDataNamesTheLineAndTheByte)
  expect_obj_error(kTetra + "# x" + nul + "\n", {"bad.obj:9", "byte 0x00"});
}

TEST(BadInputObj, EmptyFilesAndFilesWithoutFaces) {
  expect_obj_error("", {"bad.obj", "empty (0 bytes)"});
  expect_obj_error("\n\n  \t\n", {"bad.obj", "no faces"});
  expect_obj_error("# only a comment", {"bad.obj", "no faces"});
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\np 1\n", {"bad.obj", "no faces"});
  const auto file = std::filesystem::temp_directory_path() / "pbd_bad_input_empty.obj";
  std::ofstream(file).close();
  expect_words(error_of([&] { load_obj(file); }), {"pbd_bad_input_empty.obj", "empty (0 bytes)"});
}

TEST(BadInputObj, BinaryDataNamesTheLineAndTheByte) {
  expect_obj_error(std::string("\x7f" "ELF\x02\x01\x01\0\0\0", 10), {"bad.obj:1: ", "0x7f", "binary"});
  expect_obj_error(std::string("v 0 0 0\nv 1 0 0\nv 0 1\x00 0\nf 1 2 3\n", 33), {"bad.obj:3: ", "0x00", "not text"});
  expect_obj_error("v 0 0 0\x1b[0m\n", {"bad.obj:1: ", "0x1b"});
}

TEST(BadInputObj, CutAnywhereIsAMeshOrAnErrorNamingTheLine) {
  for (std::size_t n = 0; n <= kTetra.size(); ++n) {
    const std::string text = kTetra.substr(0, n);
    try {
      const TriangleMesh m = parse_obj(text, "cut.obj");
      EXPECT_GT(m.triangles.size(), 0u);
    } catch (const Error& e) {
      const std::string message = e.what();
      ASSERT_EQ(message.rfind("cut.obj", 0), 0u) << message;
      if (n > 0 && text.find('f') != std::string::npos && text.back() != '\n' && text.back() != 'f') {
        EXPECT_EQ(message.rfind("cut.obj:", 0), 0u) << "a cut line is named: " << message;
      }
    } catch (const std::exception& e) {
      FAIL() << "cut at " << n << ": not a pbd::Error: " << e.what();
    }
  }
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2", {"bad.obj:5: ", "at least 3 vertices, this one has 2"});
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 1 1", {"bad.obj:5: ", "3 coordinates, this one has 2"});
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 1.5e\nf 1 2 3\n", {"bad.obj:3: ", "\"1.5e\" is not a decimal number"});
}

TEST(BadInputObj, OversizedFilesAreRefusedBeforeReading) {
  const auto file = std::filesystem::temp_directory_path() / "pbd_bad_input_huge.obj";
  std::ofstream(file).close();
  std::filesystem::resize_file(file, kMaxObjBytes + 1);  // sparse: costs no disk
  expect_words(error_of([&] { load_obj(file); }), {"pbd_bad_input_huge.obj", "268435457 bytes", "more than"});
  std::filesystem::remove(file);
}

// --- OBJ: numbers -------------------------------------------------------------------------------------------

TEST(BadInputObj, NumbersTinyobjloaderWouldMisreadAreRefused) {
  expect_obj_error("v 0 0 0\nv 0x1p3 0 0\nv 0 1 0\nf 1 2 3\n", {"bad.obj:2: ", "\"0x1p3\" is not a decimal number"});
  expect_obj_error("v 0 0 0\nv -inf 0 0\nv 0 1 0\nf 1 2 3\n", {"bad.obj:2: ", "\"-inf\""});
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n", {"bad.obj:3: ", "beyond the float range"});
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0e441\nf 1 2 3\n", {"bad.obj:3: ", "exponent beyond 400"});
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 1,5\nf 1 2 3\n", {"bad.obj:3: ", "\"1,5\""});
  // Found by tests/fuzz: a signed int overflow inside tinyobjloader's number parser (UBSan).
  expect_obj_error("# v 0 1 0 1 0 0\nv 1.5e-21474836490 -0 +2\n", {"bad.obj:2: ", "exponent beyond 400"});
  // The forms it reads right are accepted, with their values.
  const TriangleMesh m = parse_obj("v +1 -.5 2.\nv 1e2 1E-2 -0\nv 0.25e+1 0 0 1\nf 1 2 3\n", "ok.obj");
  EXPECT_DOUBLE_EQ(m.positions(1, 0), -0.5);
  EXPECT_DOUBLE_EQ(m.positions(0, 1), 100.0);
  EXPECT_FLOAT_EQ(float(m.positions(1, 1)), 0.01f);
  EXPECT_DOUBLE_EQ(m.positions(0, 2), 2.5);
}

// --- OBJ: indices and references ----------------------------------------------------------------------------

TEST(BadInputObj, ReferencesAndIndicesNameTheLine) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_obj_error(v3 + "f 1 2 99999999999\n", {"bad.obj:4: ", "out of range"});
  expect_obj_error(v3 + "f 1 2 -2147483648\n", {"bad.obj:4: ", "out of range"});
  expect_obj_error(v3 + "f 1 2 2147483647\n", {"bad.obj:4: ", "vertex index 2147483647 is out of range"});
  expect_obj_error(v3 + "f 1/2/3/4 2 3\n", {"bad.obj:4: ", "\"1/2/3/4\" is not a vertex reference"});
  expect_obj_error(v3 + "f 1/ 2 3\n", {"bad.obj:4: ", "\"1/\""});
  expect_obj_error(v3 + "f 1// 2 3\n", {"bad.obj:4: ", "\"1//\""});
  expect_obj_error(v3 + "f 1 2 x\n", {"bad.obj:4: ", "\"x\""});
  expect_obj_error(v3 + "f 1 2 3a\n", {"bad.obj:4: ", "\"3a\""});
  expect_obj_error(v3 + "f 1/0/1 2 3\n", {"bad.obj:4: ", "index 0"});
  // Relative indices count the vertices before the face, even if more follow.
  expect_obj_error("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", {"bad.obj:3: ", "-3 is out of range (2 vertices"});
  // Positive indices may name a vertex further down; references with texture and normal indices are fine.
  EXPECT_EQ(parse_obj("f 1/1/1 2//1 3/1\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "ok.obj").triangles.size(), 1u);
}

TEST(BadInputObj, AFaceNamingAVertexTwiceIsDegenerate) {
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -3\n", {"bad.obj:4: ", "vertex 1 twice"});
  // A long face of one repeated vertex is found without quadratic work.
  std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3";
  for (int i = 0; i < 100'000; ++i) text += " 3";
  expect_obj_error(text, {"bad.obj:4: ", "vertex 3 twice"});
}

TEST(BadInputObj, FacesOfMoreThan255VerticesAreRefusedAsTinyObjLoaderCouldNotReadThem) {
  // tinyobjloader kept a face's vertex count in a byte: such files were refused when it read the meshes, and still are.
  auto polygon = [](int n) {
    std::string text;
    for (int i = 0; i < n; ++i) text += "v " + std::to_string(std::cos(i)) + " " + std::to_string(std::sin(i)) + " 0\n";
    text += "f";
    for (int i = 1; i <= n; ++i) {
      text += ' ';
      text += std::to_string(i);
    }
    return text + "\n";
  };
  EXPECT_EQ(parse_obj(polygon(255), "ok.obj").triangles.size(), 253u);
  expect_obj_error(polygon(256), {"bad.obj:257: ", "could not read every vertex of this face", "256"});
}

// --- OBJ: line endings and statements that are ignored -------------------------------------------------------

TEST(BadInputObj, LineNumbersFollowEveryLineEnding) {
  expect_obj_error("v 0 0 0\r\nv 1 0 0\r\nv 0 1 x\r\nf 1 2 3\r\n", {"bad.obj:3: "});
  expect_obj_error("v 0 0 0\rv 1 0 0\rv 0 1 x\rf 1 2 3\r", {"bad.obj:3: "});
  expect_obj_error("v 0 0 0\n\rv 1 0 0\nf 1 2 9\n", {"bad.obj:4: "});  // "\n\r" is two line ends
  EXPECT_EQ(parse_obj("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3", "ok.obj").triangles.size(), 1u);
}

TEST(BadInputObj, StatementsPbdDoesNotUseAreIgnoredNotParsed) {
  // tinyobjloader's tags allocate up to 3 × 8192 values per "t" line and copy them per shape: a small file of such
  // lines used to take gigabytes. Materials are never opened, nothing is read but the text given.
  std::string text = "mtllib /nonexistent/x.mtl\nusemtl red\no a\ng b\ns 1\nvn 0 0 1\nvt 0 0\nl 1 2\np 1\nvw 0 0 1\n";
  for (int i = 0; i < 2000; ++i) text += "t a 8192/8192/8192\n";
  text += kTetra;
  EXPECT_EQ(parse_obj(text, "ok.obj").triangles.size(), 4u);
}

}  // namespace
}  // namespace pbd
