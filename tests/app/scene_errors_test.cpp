// Every kind of bad scene input gives an InputError naming the file, the line, the key, the value and what is allowed.
#include <gtest/gtest.h>

#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

const std::string kValid = R"([simulation]
integrator = "rk4"
dt = 0.001
duration = 1.0

[bodies.jelly]
type = "jelly"
n = 3

[colliders.floor]
type = "plane"
restitution = 0.5
)";

class InputErrors : public testing::ScratchDir {
 protected:
  // The error message for a scene made from kValid with one line replaced (or appended), and optional overrides.
  std::string errorFor(const std::string& from, const std::string& to, std::vector<std::string> overrides = {}) {
    std::string text = kValid;
    if (from.empty()) text += to + "\n";
    else text.replace(text.find(from), from.size(), to);
    const auto file = write("bad.toml", text);
    try {
      loadScene(file, overrides);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error for: " << to;
    return "";
  }
};

void expectAll(const std::string& message, std::initializer_list<const char*> parts) {
  for (const char* part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing in: " << message;
}

TEST_F(InputErrors, ValidSceneLoads) {
  const SceneFile scene = loadScene(write("ok.toml", kValid));
  EXPECT_EQ(scene.system->particleCount(), 27);
  EXPECT_EQ(scene.system->colliders().size(), 1u);
  EXPECT_EQ(scene.frameCount(), 30);
}

TEST_F(InputErrors, TomlSyntaxErrorHasLineAndColumn) {
  expectAll(errorFor("n = 3", "n = = 3"), {"bad.toml:8:", "syntax error"});
}

TEST_F(InputErrors, UnknownKeySuggestsTheNearestOne) {
  expectAll(errorFor("n = 3", "n = 3\nstifness = 5"), {"bad.toml:9:", "unknown key 'bodies.jelly.stifness'"});
  expectAll(errorFor("n = 3", "n = 3\nkss = 5"), {"did you mean 'bodies.jelly.ks'?"});
  expectAll(errorFor("dt = 0.001", "dt = 0.001\nintegrater = \"rk4\""), {"did you mean 'simulation.integrator'?"});
  expectAll(errorFor("", "[camra]\nfov = 40"), {"unknown key 'camra'"});
}

TEST_F(InputErrors, WrongTypes) {
  expectAll(errorFor("dt = 0.001", "dt = \"small\""),
            {"bad.toml:3:6", "simulation.dt = \"small\"", "must be a number"});
  expectAll(errorFor("n = 3", "n = 3.5"), {"bodies.jelly.n = 3.5", "whole number"});
  expectAll(errorFor("n = 3", "n = 3\ncenter = [0, 1]"), {"bodies.jelly.center", "three numbers"});
  expectAll(errorFor("type = \"plane\"", "type = \"plane\"\nnormal = \"up\""), {"colliders.floor.normal"});
}

TEST_F(InputErrors, OutOfRangeValues) {
  expectAll(errorFor("dt = 0.001", "dt = 0"), {"simulation.dt = 0", "must be > 0"});
  expectAll(errorFor("dt = 0.001", "dt = -0.1"), {"simulation.dt = -0.1", "must be > 0"});
  expectAll(errorFor("n = 3", "n = 3\nmass = 0"), {"bodies.jelly.mass = 0", "must be > 0"});
  expectAll(errorFor("n = 3", "n = 1"), {"bodies.jelly.n = 1", "must be in [2, 894]"});
  expectAll(errorFor("n = 3", "n = 3\nks = -5"), {"bodies.jelly.ks = -5", "must be >= 0"});
  expectAll(errorFor("restitution = 0.5", "restitution = 1.5"), {"colliders.floor.restitution = 1.5", "in [0, 1]"});
  expectAll(errorFor("restitution = 0.5", "restitution = -0.1"), {"in [0, 1]"});
  expectAll(errorFor("integrator = \"rk4\"", "integrator = \"rk5\""),
            {"simulation.integrator = \"rk5\"", "explicit-euler", "pc-euler", "midpoint", "rk4"});
  expectAll(errorFor("type = \"jelly\"", "type = \"blob\""), {"bodies.jelly.type = \"blob\"", "jelly, cloth"});
}

TEST_F(InputErrors, MissingTextureFile) {
  expectAll(errorFor("n = 3", "n = 3\ntexture = \"nowhere.png\""),
            {"bodies.jelly.texture", "file not found", "nowhere.png"});
}

TEST_F(InputErrors, ClothPins) {
  const std::string cloth = "[bodies.cloth]\ntype = \"cloth\"\nnx = 3\nny = 3\npinned = ";
  EXPECT_NO_THROW(loadScene(write("c.toml", cloth + "[0, 8, \"top-edge\"]\n")));
  for (const char* bad : {"[9]", "[\"middle\"]", "[1.5]", "\"corners\""}) {
    try {
      loadScene(write("c.toml", cloth + bad + "\n"));
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      expectAll(e.what(), {"c.toml:5:", "bodies.cloth.pinned"});
    }
  }
}

TEST_F(InputErrors, MissingFileAndEmptyScene) {
  try {
    loadScene(dir() / "absent.toml");
    ADD_FAILURE();
  } catch (const InputError& e) {
    expectAll(e.what(), {"absent.toml", "not found"});
  }
  try {
    loadScene(write("empty.toml", "[simulation]\ndt = 0.01\n"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    expectAll(e.what(), {"empty.toml", "at least one body"});
  }
}

TEST_F(InputErrors, OverridesAreCheckedLikeTheFile) {
  expectAll(errorFor("", "", {"jelly.ks=-1"}), {"bodies.jelly.ks = -1", "(--set)", ">= 0"});
  expectAll(errorFor("", "", {"simulation.dt=abc"}), {"simulation.dt = \"abc\"", "must be a number"});
  expectAll(errorFor("", "", {"jelly.kss=1"}), {"unknown key 'bodies.jelly.kss'", "did you mean 'bodies.jelly.ks'?"});
  expectAll(errorFor("", "", {"no_equals_sign"}), {"--set no_equals_sign", "KEY=VALUE"});
  expectAll(errorFor("", "", {"simulation.dt.x=1"}), {"'dt' is a value"});
}

TEST_F(InputErrors, OverridesApply) {
  const auto file = write("ok.toml", kValid);
  const SceneFile scene = loadScene(file, {"jelly.ks=2800", "simulation.integrator=midpoint", "simulation.dt=2e-3",
                                           "bodies.jelly.n=4", "floor.friction=0"});
  EXPECT_EQ(scene.integrator, "midpoint");
  EXPECT_EQ(scene.dt, 2e-3);
  EXPECT_EQ(scene.system->particleCount(), 64);
  EXPECT_EQ(scene.system->springs().ks[0], 2800);
  EXPECT_EQ(scene.system->colliders()[0]->contact().friction, 0);
}

TEST_F(InputErrors, ShippedScenesLoad) {
  for (const char* name : {"jelly_slope", "jelly_elevator", "cloth_sphere", "cat_jelly"}) {
    const SceneFile scene = loadScene(testing::sourceDir() / "scenes" / (std::string(name) + ".toml"));
    EXPECT_EQ(scene.system->colliders().size(), 1u) << name;
    const bool cat = std::string(name) == "cat_jelly" || std::string(name) == "jelly_slope";
    EXPECT_EQ(scene.textures.size(), cat ? 1u : 0u) << name;  // only where named
  }
}

}  // namespace
}  // namespace wobble
