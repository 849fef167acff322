// Mesh jellies and mesh colliders through the wobble binary: bad models refused (exit 2, the file, the key and what is
// wrong, nothing written), the mesh jelly's section of scenes/README.md against the reader, and the OBJ sequence and
// PC2 of a mesh jelly keeping the model's own vertices in the file's order.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "app/output/pc2.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

// A unit cube as OBJ text: 8 `v` lines in a scrambled order (so that file order differs from any sorted one),
// 6 quads, and UVs per face.
const std::string kCubeObj =
    "v 1 1 1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    // file indices: (0,0,0)=2 (1,0,0)=3 (0,1,0)=4 (1,1,0)=5 (0,0,1)=6 (1,0,1)=7 (0,1,1)=8 (1,1,1)=1
    "f 2/1 4/2 5/3 3/4\n"   // -z
    "f 6/1 7/2 1/3 8/4\n"   // +z
    "f 2/1 6/2 8/3 4/4\n"   // -x
    "f 3/1 5/2 1/3 7/4\n"   // +x
    "f 2/1 3/2 7/3 6/4\n"   // -y
    "f 4/1 8/2 1/3 5/4\n";  // +y

std::string slurp(const fs::path& file) {
  std::ostringstream s;
  s << std::ifstream(file).rdbuf();
  return s.str();
}

int runBinary(const std::string& arguments, const fs::path& log) {
  const int status =
      std::system((std::string(WOBBLE_BINARY) + " " + arguments + " > " + log.string() + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class MeshScenes : public testing::ScratchDir {
 protected:
  void expectRefused(const std::string& obj, const std::string& keys, const std::vector<std::string>& expected,
                     const std::string& body = "jelly") {
    if (!obj.empty()) write("model.obj", obj);
    const std::string table = body == "jelly" ? "[bodies.b]\ntype = \"jelly\"\n"
                                              : "[bodies.b]\ntype = \"jelly\"\nn = 3\n[colliders.c]\ntype = \"mesh\"\n";
    const fs::path scene = write("bad.toml", table + "mesh = \"model.obj\"\n" + keys);
    const fs::path out = dir() / "out", log = dir() / "log.txt";
    EXPECT_EQ(runBinary("run " + scene.string() + " --out " + out.string(), log), 2) << slurp(log);
    const std::string message = slurp(log);
    for (const std::string& part : expected)
      EXPECT_NE(message.find(part), std::string::npos) << part << " in " << message;
    EXPECT_FALSE(fs::exists(out)) << "written despite the error";
  }
};

TEST_F(MeshScenes, BadModelsAreRefused) {
  expectRefused("", "", {"bad.toml:3:", "mesh", "file not found", "model.obj"});
  std::string open = kCubeObj.substr(0, kCubeObj.rfind("f "));  // drop the +y face
  expectRefused(open, "", {"model.obj", "not closed", "4 boundary edges", "between vertices"});
  expectRefused("v 0 0 0\n", "", {"model.obj", "empty"});
  expectRefused("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "", {"model.obj", "degenerate"});
  expectRefused("v nan 0 0\n" + kCubeObj, "", {"model.obj", "vertex 1", "not finite"});
  expectRefused("v 0 0 0\nf 1 2 3\n", "", {"model.obj", "line 2", "out of range"});
  expectRefused(kCubeObj + "v 0 0 2\nf 2 3 9\n", "", {"model.obj", "not manifold"});
  expectRefused(kCubeObj, "scale = 0\n", {"bodies.b.scale = 0", "> 0"});
  expectRefused(kCubeObj, "cells = 880\n", {"bodies.b.cells = 880"});  // over the memory budget
  expectRefused(kCubeObj, "n = 4\n", {"unknown key", "bodies.b.n"});
  expectRefused(kCubeObj, "scale = -1\n", {"colliders.c.scale = -1"}, "collider");
  expectRefused("v 0 0 0\n", "", {"colliders.c.mesh", "empty"}, "collider");
}

// An open mesh is a fine collider (a plate), but not a jelly.
TEST_F(MeshScenes, OpenMeshIsACollider) {
  write("plate.obj", "v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nf 1 3 2\nf 1 4 3\n");
  const fs::path scene = write("ok.toml",
                               "[simulation]\nduration = 0.1\n[render]\npng = false\n[bodies.b]\ntype = \"jelly\"\n"
                               "n = 3\nsize = 1\ncenter = [0, 1, 0]\n[colliders.plate]\ntype = \"mesh\"\n"
                               "mesh = \"plate.obj\"\n");
  EXPECT_EQ(runBinary("run " + scene.string() + " --out " + (dir() / "out").string(), dir() / "log.txt"), 0)
      << slurp(dir() / "log.txt");
}

// The `v` lines of every frame and the PC2's points are the model's vertices, in the file's order and count; at frame
// 1 they are the file's positions placed by center and scale.
TEST_F(MeshScenes, OutputKeepsTheModelsVertexOrder) {
  write("cube.obj", kCubeObj);
  const fs::path scene = write("cube.toml",
                               "[simulation]\nduration = 0.2\nfps = 10\n[output]\npc2 = true\n[render]\npng = false\n"
                               "[bodies.b]\ntype = \"jelly\"\nmesh = \"cube.obj\"\ncells = 3\nscale = 2\n"
                               "center = [0, 5, 0]\n");
  ASSERT_EQ(runBinary("run " + scene.string() + " --out " + (dir() / "out").string(), dir() / "log.txt"), 0)
      << slurp(dir() / "log.txt");
  const auto vLines = [](const fs::path& obj) {
    std::vector<Vec3> v;
    std::ifstream in(obj);
    for (std::string line; std::getline(in, line);)
      if (line.rfind("v ", 0) == 0) {
        std::istringstream s(line.substr(2));
        Vec3 p;
        s >> p.x() >> p.y() >> p.z();
        v.push_back(p);
      }
    return v;
  };
  const std::vector<Vec3> first = vLines(dir() / "out/mesh/b_0001.obj");
  ASSERT_EQ(first.size(), 8u);
  std::istringstream model(kCubeObj);
  for (std::size_t i = 0; i < 8; ++i) {
    std::string tag;
    Vec3 p;
    model >> tag >> p.x() >> p.y() >> p.z();
    EXPECT_LT((first[i] - (Vec3(0, 5, 0) + 2 * (p - Vec3::Constant(0.5)))).norm(), 1e-5) << i;
  }
  const Pc2File cache = readPc2(dir() / "out/mesh/b.pc2");
  ASSERT_EQ(cache.header.points, 8);
  const std::vector<Vec3> last = vLines(dir() / "out/mesh/b_0002.obj");
  for (int i = 0; i < 8; ++i) {
    EXPECT_LT((cache.at(0, i).cast<double>() - first[i]).norm(), 1e-5) << i;
    EXPECT_LT((cache.at(1, i).cast<double>() - last[i]).norm(), 1e-5) << i;
  }
}

// scenes/README.md's section for a mesh jelly lists exactly the keys the reader accepts there.
TEST_F(MeshScenes, MeshJellyKeysAreDocumented) {
  write("cube.obj", kCubeObj);
  std::set<std::string> accepted, documented;
  try {
    loadScene(write("probe.toml", "[bodies.c]\ntype = \"jelly\"\nmesh = \"cube.obj\"\nzzz = 1\n"));
    ADD_FAILURE() << "no error for the probe";
  } catch (const InputError& e) {
    const std::string m = e.what();
    const auto from = m.find("(allowed here: ");
    ASSERT_NE(from, std::string::npos) << m;
    std::stringstream list(m.substr(from + 15, m.rfind(')') - from - 15));
    for (std::string k; std::getline(list, k, ',');) accepted.insert(k.substr(k.find_first_not_of(' ')));
  }
  std::ifstream in(testing::sourceDir() / "scenes/README.md");
  bool inside = false;
  const std::regex row(R"(^\| `([a-z_0-9]+)` \|)");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("### ", 0) == 0) inside = line == "### `[bodies.NAME]` with `type = \"jelly\"` and `mesh`";
    std::smatch m;
    if (inside && std::regex_search(line, m, row)) documented.insert(m[1]);
  }
  EXPECT_EQ(accepted, documented);
}

}  // namespace
}  // namespace wobble
