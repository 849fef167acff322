// scenes/README.md documents exactly the keys the scene reader accepts, table by table: a key the reader takes but
// the README omits, or a documented key the reader rejects, fails here.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "app/scene/body_kinds.h"
#include "app/scene/collider_kinds.h"
#include "app/scene/input_error.h"
#include "app/scene/material_kinds.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

using Keys = std::set<std::string>;

// Keys in the "| `key` |" rows of the README section whose heading line is exactly heading.
Keys documentedKeys(const std::string& heading) {
  std::ifstream in(testing::sourceDir() / "scenes/README.md");
  Keys keys;
  bool inside = false;
  const std::regex row(R"(^\| `([a-z_0-9]+)` \|)");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("### ", 0) == 0) inside = line == heading;
    std::smatch m;
    if (inside && std::regex_search(line, m, row)) keys.insert(m[1]);
  }
  return keys;
}

Keys& operator+=(Keys& a, const Keys& b) {
  a.insert(b.begin(), b.end());
  return a;
}

class SceneDocs : public testing::ScratchDir {
 protected:
  // The reader's own list of keys for a table: provoke an unknown-key error there and read "(allowed here: ...)".
  Keys acceptedKeys(const std::string& scene_text) {
    try {
      loadScene(write("probe.toml", scene_text));
    } catch (const InputError& e) {
      const std::string m = e.what();
      const auto from = m.find("(allowed here: ");
      if (from == std::string::npos) {
        ADD_FAILURE() << m;
        return {};
      }
      std::stringstream list(m.substr(from + 15, m.rfind(')') - from - 15));
      Keys keys;
      for (std::string k; std::getline(list, k, ',');) keys.insert(k.substr(k.find_first_not_of(' ')));
      return keys;
    }
    ADD_FAILURE() << "no error for the probe";
    return {};
  }
};

const std::string kBody = "[bodies.b]\ntype = \"jelly\"\nn = 2\n";

TEST_F(SceneDocs, SimulationAndOutput) {
  EXPECT_EQ(acceptedKeys("[simulation]\nzzz = 1\n" + kBody), documentedKeys("### `[simulation]`"));
  EXPECT_EQ(acceptedKeys("[output]\nzzz = 1\n" + kBody), documentedKeys("### `[output]`"));
}

TEST_F(SceneDocs, Contact) {
  EXPECT_EQ(acceptedKeys("[contact]\nzzz = 1\n" + kBody), documentedKeys("### `[contact]`"));
}

TEST_F(SceneDocs, CameraAndRender) {
  EXPECT_EQ(acceptedKeys("[camera]\nzzz = 1\n" + kBody), documentedKeys("### `[camera]`"));
  EXPECT_EQ(acceptedKeys("[render]\nzzz = 1\n" + kBody), documentedKeys("### `[render]`"));
}

TEST_F(SceneDocs, Bodies) {  // every kind the reader knows (body_kinds.h), each with its own section
  ASSERT_FALSE(bodyTypes().empty());
  for (const std::string& type : bodyTypes()) {
    const Keys documented = documentedKeys("### `[bodies.NAME]` with `type = \"" + type + "\"`");
    EXPECT_FALSE(documented.empty()) << type << " has no section";
    EXPECT_EQ(acceptedKeys("[bodies.c]\ntype = \"" + type + "\"\nzzz = 1\n"), documented) << type;
  }
}

// A material's own keys (material_kinds.h) have a section of their own, read on top of the jelly's.
TEST_F(SceneDocs, Materials) {
  const Keys jelly = documentedKeys("### `[bodies.NAME]` with `type = \"jelly\"`");
  for (const std::string& material : materialTypes()) {
    Keys documented = jelly;
    documented += documentedKeys("### `[bodies.NAME]` with `material = \"" + material + "\"`");
    EXPECT_EQ(acceptedKeys("[bodies.c]\ntype = \"jelly\"\nmaterial = \"" + material + "\"\nzzz = 1\n"), documented)
        << material;
  }
  EXPECT_FALSE(documentedKeys("### `[bodies.NAME]` with `material = \"gelatine\"`").empty());
}

TEST_F(SceneDocs, Colliders) {
  const Keys common = documentedKeys("### `[colliders.NAME]`, every type");
  ASSERT_FALSE(common.empty());
  ASSERT_FALSE(colliderTypes().empty());
  for (const std::string& type : colliderTypes()) {  // every kind the reader knows (collider_kinds.h)
    Keys documented = common;
    const Keys own = documentedKeys("### `[colliders.NAME]` with `type = \"" + type + "\"`");
    EXPECT_FALSE(own.empty()) << type << " has no section";
    documented += own;
    // A mesh collider needs its model before the reader gets to the unknown key.
    const std::string required =
        type == "mesh" ? (write("plate.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\n"), "mesh = \"plate.obj\"\n") : "";
    EXPECT_EQ(acceptedKeys(kBody + "[colliders.c]\ntype = \"" + type + "\"\n" + required + "zzz = 1\n"), documented)
        << type;
  }
}

}  // namespace
}  // namespace wobble
