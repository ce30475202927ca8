// Scene files: defaults, formulas, the resolved text, and the corpus of malformed scenes, each
// rejected with its own message naming the file, line and key.
#include "host/scene/scene_parser.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "kernels/core/error.h"
#include "tests/support/scratch_folder.h"

namespace romp::scene {
namespace {

namespace fs = std::filesystem;

const char* const kCube = R"(
[parameters]
speed = 2.0

[domain]
size = [1.0, 1.0, 1.0]
dx = 0.05

[time]
end = 0.5
frame_rate = 20

[materials.jelly]
preset = "jelly"

[[objects]]
material = "jelly"
velocity = ["speed", 0, "-speed * 0.5"]
shape = { type = "box", center = [0.5, 0.5, 0.5], size = [0.5, 0.5, 0.5] }
)";

TEST(SceneParser, FillsDefaultsAndEvaluatesFormulas) {
  const Scene scene = parse_scene(kCube, "cube.toml");
  EXPECT_EQ(scene.name, "cube");
  EXPECT_EQ(scene.domain_cells[0], 20);
  EXPECT_EQ(scene.frame_count, 10);
  EXPECT_EQ(scene.fixed_dt, 0.0);
  EXPECT_EQ(scene.cfl, 0.5);
  EXPECT_EQ(scene.wall_cells, 3);
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].youngs_modulus, 1e5);
  EXPECT_EQ(scene.materials[0].poissons_ratio, 0.2);
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].velocity, Vec3<double>(2.0, 0.0, -1.0));
  EXPECT_EQ(scene.objects[0].sampling.per_cell, 2);
  EXPECT_EQ(scene.gravity, Vec3<double>(0.0, -9.81, 0.0));
  EXPECT_EQ(scene.output.file, "runs/cube.h5");
  EXPECT_FALSE(scene.sweep.has_value());
}

// end × frame_rate beyond int32 once wrapped to "-2147483648 frames" and a run of no substep.
TEST(SceneParser, AFrameCountBeyondRangeIsRefusedNotWrapped) {
  std::string text = kCube;
  text.replace(text.find("end = 0.5"), 9, "end = 1e6");
  text.replace(text.find("frame_rate = 20"), 15, "frame_rate = 1e7");
  const std::string error = test::error_message([&] { parse_scene(text, "cube.toml"); });
  EXPECT_NE(error.find("cube.toml"), std::string::npos) << error;
  EXPECT_NE(error.find("frame_rate"), std::string::npos) << error;
  EXPECT_NE(error.find("end × frame_rate (the frame count) is 1e+13; it must be at most 2147483647"), std::string::npos)
      << error;
}

// dt = 1e-300 was accepted and then ran with the CFL step (it is 0 in float); max_dt = 1e-200 passed
// `romp check` and failed in `romp run`.
TEST(SceneParser, StepsThatVanishInFloatAreRefused) {
  for (const std::string& step : {std::string("dt = 1e-300"), std::string("max_dt = 1e-200")}) {
    std::string text = kCube;
    text.replace(text.find("frame_rate = 20"), 15, "frame_rate = 20\n" + step);
    const std::string error = test::error_message([&] { parse_scene(text, "cube.toml"); });
    EXPECT_NE(error.find("cube.toml:"), std::string::npos) << error;
    EXPECT_NE(error.find("time." + step.substr(0, step.find(' '))), std::string::npos) << error;
  }
  std::string text = kCube;
  text.replace(text.find("frame_rate = 20"), 15, "frame_rate = 20\ndt = 1e-6");
  EXPECT_EQ(parse_scene(text, "cube.toml").fixed_dt, 1e-6);
}

// `romp check /dev/urandom` once read gigabytes, and a scene of 100,000 parameters took 88 s to parse
// (each key was looked up in a list of the keys read so far; now a set).
TEST(SceneParser, HostileFilesAreRefusedAndManyParametersParseQuickly) {
  EXPECT_NE(test::error_message([] { load_scene("/dev/urandom"); }).find("/dev/urandom: not a regular file"),
            std::string::npos);
  const test::ScratchFolder folder;
  {
    std::ofstream big(folder.file("big.toml"));
    big << "# " << std::string(9 << 20, 'x') << "\n";
  }
  EXPECT_NE(test::error_message([&] { load_scene(folder.file("big.toml")); }).find("a scene file may hold at most"),
            std::string::npos);

  std::string text = kCube;
  std::string parameters = "[parameters]\nspeed = 2.0\n";
  for (int k = 0; k < 100000; ++k) parameters += "p" + std::to_string(k) + " = " + std::to_string(k) + "\n";
  text.replace(text.find("[parameters]\nspeed = 2.0\n"), 24, parameters);
  EXPECT_EQ(parse_scene(text, "cube.toml").parameters.size(), 100001u);
}

// Names reach the terminal: an escape sequence in one once went there raw.
TEST(SceneParser, NamesWithControlCharactersAreRefused) {
  const std::string scene_name = test::error_message(
      [] { parse_scene("[scene]\nname = \"cube\\u001b[31m\"\n" + std::string(kCube), "cube.toml"); });
  EXPECT_NE(scene_name.find("scene.name: must be a non-empty name without slashes or control characters"),
            std::string::npos)
      << scene_name;
  std::string text = kCube;
  text.replace(text.find("material = \"jelly\""), 18, "material = \"jelly\"\nname = \"a\\tb\"");
  const std::string object_name = test::error_message([&] { parse_scene(text, "cube.toml"); });
  EXPECT_NE(object_name.find("name: must not hold control characters"), std::string::npos) << object_name;
}

// A substep's colliders, pokes and tractions are chosen on the device by bit masks: more than 64 of any are
// refused by the scene's key, not found out by the engine.
TEST(SceneParser, MoreThan64CollidersPokesOrTractionsAreRefusedByKey) {
  const auto repeated = [](const std::string& table, int count) {
    std::string text;
    for (int i = 0; i < count; ++i) text += table;
    return text;
  };
  const std::string collider = "\n[[colliders]]\ntype = \"plane\"\npoint = [0, 0.1, 0]\nnormal = [0, 1, 0]\n";
  const std::string poke =
      "\n[[loads.pokes]]\nregion = { type = \"sphere\", center = [0.5, 0.5, 0.5], radius = 0.1 }\n"
      "acceleration = [0, 1, 0]\nend = 0.1\n";
  const std::string traction =
      "\n[[loads.tractions]]\nregion = { type = \"sphere\", center = [0.5, 0.5, 0.5], radius = 0.1 }\n"
      "traction = [0, 1, 0]\n";
  for (const auto& [table, key] : {std::pair<std::string, std::string>{collider, "colliders"},
                                   {poke, "loads.pokes"},
                                   {traction, "loads.tractions"}}) {
    EXPECT_NO_THROW(parse_scene(kCube + repeated(table, 64), "cube.toml")) << key;
    const std::string message = test::error_message([&] { parse_scene(kCube + repeated(table, 65), "cube.toml"); });
    EXPECT_NE(message.find("cube.toml"), std::string::npos) << message;
    EXPECT_NE(message.find(key + ": at most 64 entries, got 65"), std::string::npos) << message;
  }
}

TEST(SceneParser, TheImplicitIntegratorAllowsALargerCfl) {
  EXPECT_EQ(parse_scene(kCube, "cube.toml").integrator, "explicit");
  std::string text = kCube;
  text.replace(text.find("frame_rate = 20"), 15, "frame_rate = 20\ncfl = 20\n\n[solver]\nintegrator = \"implicit\"");
  const Scene scene = parse_scene(text, "cube.toml");
  EXPECT_EQ(scene.integrator, "implicit");
  EXPECT_EQ(scene.cfl, 20.0);
  EXPECT_NE(scene.resolved_text.find("integrator = \"implicit\""), std::string::npos) << scene.resolved_text;
}

TEST(SceneParser, OverridesReplaceDeclaredParameters) {
  const Scene scene = parse_scene(kCube, "cube.toml", {{"speed", 4.0}});
  EXPECT_EQ(scene.objects[0].velocity, Vec3<double>(4.0, 0.0, -2.0));
  EXPECT_EQ(scene.parameters.at("speed"), 4.0);
  EXPECT_THROW(parse_scene(kCube, "cube.toml", {{"sped", 4.0}}), Error);
}

TEST(SceneParser, ResolvedTextIsACompleteSceneThatResolvesToItself) {
  const Scene scene = parse_scene(kCube, "cube.toml", {{"speed", 3.0}});
  EXPECT_NE(scene.resolved_text.find("cfl = 0.5"), std::string::npos) << scene.resolved_text;
  EXPECT_NE(scene.resolved_text.find("youngs_modulus = 100000"), std::string::npos) << scene.resolved_text;
  const Scene again = parse_scene(scene.resolved_text, "cube.toml");
  EXPECT_EQ(again.resolved_text, scene.resolved_text);
  EXPECT_EQ(again.objects[0].velocity, Vec3<double>(3.0, 0.0, -1.5));
}

// Every file in tests/data/scenes/invalid starts with "# expect: <text>"; parsing must fail with a
// message that starts with the file name (then line and column where the problem has a place) and
// contains <text>, which names the key and the allowed values.
TEST(SceneParser, RejectsEveryMalformedSceneWithItsOwnMessage) {
  const fs::path folder = fs::path(ROMP_TEST_DATA_DIR) / "scenes" / "invalid";
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".toml") continue;
    std::ifstream in(entry.path());
    std::string first_line;
    std::getline(in, first_line);
    const std::string prefix = "# expect: ";
    ASSERT_EQ(first_line.rfind(prefix, 0), 0u) << entry.path() << " lacks its '# expect:' line";
    const std::string expected = first_line.substr(prefix.size());
    const std::string file = entry.path().string();
    try {
      load_scene(file);
      ADD_FAILURE() << file << " was accepted";
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.rfind(file + ":", 0), 0u) << "the message must start with the file: " << message;
      EXPECT_NE(message.find(expected), std::string::npos)
          << file << ": expected \"" << expected << "\" in\n  " << message;
    }
    ++checked;
  }
  EXPECT_GE(checked, 30);
}

}  // namespace
}  // namespace romp::scene
