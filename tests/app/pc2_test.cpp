// The PC2 point cache of `wobble run --pc2` read byte by byte here (not with app/pc2.h's reader): its header per the
// format (signature, version 1, point count, start frame, sample rate, sample count), and every sample equal, point
// by point, to the `v` lines of the OBJ frame it stands for; the base OBJ; a blown-up and an interrupted run's cache,
// a full disk; the vertex order's invariant on a hand-made mesh; the scene's colour and texture in the MTL, as
// assimp reads it.
#include <signal.h>

#include <gtest/gtest.h>

#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "app/commands/run_command.h"
#include "app/output/obj_text.h"
#include "app/output/obj_vertex_order.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"
#include "tests/app/small_scene.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::linesStartingWith;
using testing::slurpFile;

struct Pc2Bytes {
  std::string signature;
  std::int32_t version = 0, points = 0, samples = 0;
  float start = 0, rate = 0;
  std::vector<std::array<float, 3>> positions;
  std::size_t file_size = 0;
};

// The format read by hand: 12 signature bytes, then little-endian int32, int32, float, float, int32, then floats.
Pc2Bytes readPc2Bytes(const fs::path& file) {
  const std::string bytes = slurpFile(file);
  Pc2Bytes p;
  p.file_size = bytes.size();
  if (bytes.size() < 32) return p;
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= std::uint32_t(static_cast<unsigned char>(bytes[at + k])) << (8 * k);
    return v;
  };
  const auto f32 = [&](std::size_t at) {
    const std::uint32_t bits = u32(at);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  };
  p.signature = bytes.substr(0, 12);
  p.version = std::int32_t(u32(12));
  p.points = std::int32_t(u32(16));
  p.start = f32(20);
  p.rate = f32(24);
  p.samples = std::int32_t(u32(28));
  for (std::size_t at = 32; at + 12 <= bytes.size(); at += 12)
    p.positions.push_back({f32(at), f32(at + 4), f32(at + 8)});
  return p;
}

std::vector<std::array<float, 3>> objVertices(const fs::path& obj) {
  std::ifstream in(obj);
  std::vector<std::array<float, 3>> v;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("v ", 0) == 0) {
      std::istringstream fields(line.substr(2));
      std::array<float, 3> p{};
      fields >> p[0] >> p[1] >> p[2];
      v.push_back(p);
    }
  return v;
}

std::string frameName(const std::string& body, int frame, const char* extension) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%04d.%s", body.c_str(), frame, extension);
  return name;
}

class PointCache : public testing::ScratchDir {
 protected:
  // A textured jelly (n = 3: 26 surface particles) and a coloured 4 x 5 cloth (20), falling onto a floor.
  fs::path scene(const std::string& extra = "") {
    copyCatTexture();
    return write("small.toml",
                 testing::smallSceneText({.duration = "0.3", .jelly = "color = [0.9, 0.8, 0.7]\n", .rest = R"(
[bodies.sheet]
type = "cloth"
nx = 4
ny = 5
size = [1.0, 1.0]
center = [2, 1, 0]
color = [0.2, 0.5, 0.9]
material = "jelly"
)" + extra}));
  }
  RunOptions options(const fs::path& file) {
    RunOptions o;
    o.scene = file;
    o.out = dir() / "out";
    o.render.render = "none";
    o.pc2 = true;
    return o;
  }
  // Every sample of OUT/mesh/<body>.pc2 equals the v lines of its OBJ frame, first..last.
  void expectCacheMatchesFrames(const std::string& body, int points, int first, int last) {
    const fs::path mesh = dir() / "out/mesh";
    const Pc2Bytes p = readPc2Bytes(mesh / (body + ".pc2"));
    EXPECT_EQ(p.signature, std::string("POINTCACHE2\0", 12));
    EXPECT_EQ(p.version, 1);
    EXPECT_EQ(p.points, points);
    EXPECT_EQ(p.start, float(first));
    EXPECT_EQ(p.rate, 1.0f);
    EXPECT_EQ(p.samples, last - first + 1);
    ASSERT_EQ(p.file_size, 32 + std::size_t(points) * (last - first + 1) * 12);
    for (int frame = first; frame <= last; ++frame) {
      const auto v = objVertices(mesh / frameName(body, frame, "obj"));
      ASSERT_EQ(v.size(), std::size_t(points)) << body << " frame " << frame;
      for (int i = 0; i < points; ++i)
        ASSERT_EQ(p.positions[std::size_t(frame - first) * points + i], v[i])
            << body << " frame " << frame << " v " << i + 1;
    }
    // The base mesh: the first frame's file, but for the name of its material library.
    const auto base = linesStartingWith(mesh / (body + ".obj"), ""),
               sequence = linesStartingWith(mesh / frameName(body, first, "obj"), "");
    ASSERT_EQ(base.size(), sequence.size());
    for (std::size_t i = 0; i < base.size(); ++i)
      if (base[i].rfind("mtllib", 0) != 0) {
        EXPECT_EQ(base[i], sequence[i]) << body << ".obj line " << i + 1;
      }
    EXPECT_EQ(linesStartingWith(mesh / (body + ".obj"), "mtllib"), std::vector<std::string>{"mtllib " + body + ".mtl"});
  }
};

TEST_F(PointCache, SamplesEqualTheObjFramesInVOrder) {
  const RunReport r = runScene(options(scene()));
  ASSERT_FALSE(r.blow_up);
  ASSERT_EQ(r.frames_written, 6);
  expectCacheMatchesFrames("jelly", 3 * 3 * 3 - 1, 1, 6);
  expectCacheMatchesFrames("sheet", 4 * 5, 1, 6);
  // The bodies move: the cache is not six copies of one frame.
  const Pc2Bytes p = readPc2Bytes(dir() / "out/mesh/jelly.pc2");
  EXPECT_LT(p.positions[5 * 26][1], p.positions[0][1] - 0.05f);
  const auto j = nlohmann::json::parse(slurpFile(dir() / "out/run.json"));
  EXPECT_EQ(j["overrides"],
            nlohmann::json::array({"output.pc2=true", "render.png=false", "render.exr=false", "render.video=false"}))
      << j["overrides"].dump();
}

TEST_F(PointCache, AFrameRangeStartsAtItsFirstFrame) {
  RunOptions o = options(scene());
  o.frames = "3:5";
  ASSERT_EQ(runScene(o).frames_written, 3);
  expectCacheMatchesFrames("jelly", 26, 3, 5);
}

TEST_F(PointCache, SceneKeyAndItsDefault) {
  RunOptions o = options(scene());
  o.pc2 = false;
  runScene(o);  // off by default; the sequence is written as before
  EXPECT_FALSE(fs::exists(dir() / "out/mesh/jelly.pc2"));
  EXPECT_FALSE(fs::exists(dir() / "out/mesh/jelly.obj"));
  EXPECT_TRUE(fs::exists(dir() / "out/mesh/jelly_0006.obj"));
  // [output] pc2 = true without the sequence: the cache and its base mesh only.
  o.scene = scene("\n[output]\nobj = false\npc2 = true\n");
  const RunReport r = runScene(o);
  EXPECT_GT(r.files_cleared, 0);
  EXPECT_TRUE(fs::exists(dir() / "out/mesh/jelly.pc2"));
  EXPECT_TRUE(fs::exists(dir() / "out/mesh/jelly.obj"));
  EXPECT_FALSE(fs::exists(dir() / "out/mesh/jelly_0001.obj"));
  EXPECT_EQ(readPc2Bytes(dir() / "out/mesh/sheet.pc2").samples, 6);
  // A rerun without it removes the earlier run's cache: the folder never mixes two runs.
  o.scene = scene();
  runScene(o);
  EXPECT_FALSE(fs::exists(dir() / "out/mesh/jelly.pc2"));
  EXPECT_FALSE(fs::exists(dir() / "out/mesh/jelly.obj"));
}

TEST_F(PointCache, ABlownUpRunKeepsAValidCacheOfItsFrames) {
  // ks 1e6 with dt 0.002: omega h ~ 2.8, far past explicit Euler's limit (as run_test.cpp's blow-up).
  RunOptions o = options(scene());
  o.integrator = "explicit-euler";
  o.sets = {"jelly.ks=1e6", "simulation.duration=2"};
  const RunReport r = runScene(o);
  ASSERT_TRUE(r.blow_up);
  ASSERT_GT(r.frames_written, 0);
  EXPECT_FALSE(fs::exists(dir() / "out/mesh" / frameName("jelly", r.frames_written + 1, "obj")));
  expectCacheMatchesFrames("jelly", 26, 1, r.frames_written);
  expectCacheMatchesFrames("sheet", 20, 1, r.frames_written);
  for (const auto& entry : fs::directory_iterator(dir() / "out/mesh"))
    EXPECT_NE(entry.path().filename().string()[0], '.') << "temporary file left: " << entry.path();
}

TEST_F(PointCache, AnInterruptedRunKeepsAValidCacheOfItsFrames) {
  // 400 frames, rendered small: SIGINT after the second frame's picture stops it after a complete frame.
  const fs::path log = dir() / "log.txt";
  const pid_t child = testing::startWobble("run " + scene().string() + " --pc2 --render png --resolution 32x18 " +
                                               "--set simulation.duration=20 --out " + (dir() / "out").string(),
                                           log);
  ASSERT_TRUE(testing::waitUntil(child, [&] { return fs::exists(dir() / "out/frames/small_0002.png"); }))
      << slurpFile(log);
  ::kill(child, SIGINT);
  EXPECT_EQ(testing::waitExit(child), 130) << slurpFile(log);
  const auto j = nlohmann::json::parse(slurpFile(dir() / "out/run.json"));
  ASSERT_TRUE(j["interrupted"].get<bool>());
  const int written = j["frames"]["written"];
  ASSERT_TRUE(written >= 2 && written < 400) << written;
  expectCacheMatchesFrames("jelly", 26, 1, written);
  expectCacheMatchesFrames("sheet", 20, 1, written);
}

TEST_F(PointCache, EveryWriteCheckedOnAFullDisk) {
  // The checked writes in order: the carried texture and scene (OUT/scene), the texture, the two caches' headers;
  // frame 1: per body mtl, obj, base mtl, base obj, sample; frames 2..6: per body mtl, obj, sample (45 so far); the
  // two headers' final counts; run.json. A failure injected at any kind fails the run and leaves no temporary file; a
  // cache only once it is complete.
  const fs::path file = scene(), log = dir() / "log.txt";
  ASSERT_EQ(testing::runWobble("run " + file.string() + " --render none --pc2 --out " + (dir() / "clean").string(),
                               log),
            0)
      << slurpFile(log);
  for (int n : {1, 2, 3, 4, 5, 6, 8, 9, 10, 15, 22, 32, 45, 46, 47, 48}) {
    const fs::path out = dir() / ("fail" + std::to_string(n));
    EXPECT_EQ(testing::runWobble("run " + file.string() + " --render none --pc2 --out " + out.string(), log,
                                 "WOBBLE_FAIL_WRITE_AFTER=" + std::to_string(n)),
              1)
        << n << ": " << slurpFile(log);
    EXPECT_NE(slurpFile(log).find("No space left on device"), std::string::npos) << n << ": " << slurpFile(log);
    const auto files = testing::expectCompleteFiles(out, dir() / "clean");
    for (const fs::path& f : files)
      EXPECT_TRUE(n >= 47 || f.extension() != ".pc2") << n << ": a cache of a failed run: " << f;
    if (n == 48) {
      EXPECT_TRUE(fs::exists(out / "mesh/sheet.pc2")) << "the count above is off";
    }
  }
}

TEST(ObjVertexOrder, OneVPerParticleInFirstUseOrderWhateverThePositions) {
  // Four surface vertices over three particles: vertex 3 is a seam copy of particle 7 (vertex 0's).
  SurfaceMesh mesh;
  mesh.particle = {7, 2, 5, 7};
  mesh.uv = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  mesh.triangles = {{0, 1, 2}, {3, 2, 1}};
  const ObjVertexOrder order(mesh);
  EXPECT_EQ(order.first_vertex, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(order.line_of, (std::vector<int>{0, 1, 2, 0}));
  // Particles 2 and 5 at one place keep two v lines (assimp's exporter merged them); the seam copy shares one.
  SurfaceFrame frame;
  frame.positions = {{0, 0, 0}, {1, 2, 3}, {1, 2, 3}, {0, 0, 0}};
  frame.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  const std::string text = objText("b", mesh, order, frame, "b.mtl");
  std::istringstream in(text);
  std::vector<std::string> v, f;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) == 0) v.push_back(line);
    if (line.rfind("f ", 0) == 0) f.push_back(line);
  }
  EXPECT_EQ(v, (std::vector<std::string>{"v 0 0 0", "v 1 2 3", "v 1 2 3"}));
  EXPECT_EQ(f, (std::vector<std::string>{"f 1/1/1 2/2/2 3/3/3", "f 1/4/4 3/3/3 2/2/2"}));
}

TEST_F(PointCache, MaterialsFollowTheScene) {
  runScene(options(scene()));
  for (const char* body : {"jelly", "sheet"})
    for (const fs::path& obj :
         {dir() / "out/mesh" / (std::string(body) + ".obj"), dir() / "out/mesh" / frameName(body, 3, "obj")}) {
      Assimp::Importer importer;
      const aiScene* s = importer.ReadFile(obj.string(), 0);
      ASSERT_TRUE(s && s->mNumMeshes == 1) << obj << ": " << importer.GetErrorString();
      const aiMaterial* m = s->mMaterials[s->mMeshes[0]->mMaterialIndex];
      aiColor3D kd;
      ASSERT_EQ(m->Get(AI_MATKEY_COLOR_DIFFUSE, kd), AI_SUCCESS);
      aiString texture;
      const bool textured = m->GetTexture(aiTextureType_DIFFUSE, 0, &texture) == AI_SUCCESS;
      if (std::string(body) == "jelly") {  // the scene's colour, which multiplies the texture
        EXPECT_EQ(kd, aiColor3D(0.9f, 0.8f, 0.7f)) << obj;
        ASSERT_TRUE(textured) << obj;
        EXPECT_STREQ(texture.C_Str(), "cat.png");
      } else {
        EXPECT_EQ(kd, aiColor3D(0.2f, 0.5f, 0.9f)) << obj;
        EXPECT_FALSE(textured) << obj;
      }
    }
  // Without a colour key, the scene's default for the kind (scenes/README.md): a jelly red, white when textured.
  runScene(options(write("plain.toml", "[bodies.red]\ntype = \"jelly\"\nn = 2\n[simulation]\nduration = 0.1\n")));
  EXPECT_EQ(linesStartingWith(dir() / "out/mesh/red_0001.mtl", "Kd"), std::vector<std::string>{"Kd 0.8 0.12 0.15"});
}

}  // namespace
}  // namespace wobble
