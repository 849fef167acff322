// `wobble run` end to end: OBJ sequences that assimp reads back (counts, UVs, order), frame ranges, several bodies,
// run.json, blow-ups that keep earlier frames, exit statuses, and byte-identical reruns.
#include <gtest/gtest.h>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include <fstream>
#include <set>
#include <sstream>

#include "app/commands/run_command.h"
#include "app/scene/input_error.h"
#include "sim/bodies/jelly.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"
#include "tests/app/small_scene.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The position/uv part of each "f" line: assimp numbers normals by distinct value, which changes as faces bend.
std::vector<std::string> faceCorners(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> faces;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("f ", 0) != 0) continue;
    std::istringstream corners(line.substr(2));
    std::string face;
    for (std::string c; corners >> c;) face += c.substr(0, c.rfind('/')) + " ";
    faces.push_back(face);
  }
  return faces;
}

using testing::linesStartingWith;

class Run : public testing::ScratchDir {
 protected:
  fs::path scene(const std::string& extra = "") {
    copyCatTexture();
    return write("small.toml", testing::smallSceneText({.rest = extra}));
  }
  // These tests are about simulation and OBJ output: no frames rendered (render_test.cpp covers those).
  RunOptions options(const fs::path& file) {
    RunOptions o;
    o.scene = file;
    o.out = dir() / "out";
    o.render.render = "none";
    return o;
  }
};

TEST_F(Run, ObjSequenceRoundTripsThroughAssimp) {
  const RunReport r = runScene(options(scene()));
  ASSERT_FALSE(r.blow_up);
  EXPECT_EQ(r.frames_written, 4);
  const fs::path mesh = dir() / "out/mesh";
  const Body reference = buildJelly("jelly", {.n = 3});
  const std::vector<std::string> faces = faceCorners(mesh / "jelly_0001.obj");
  ASSERT_EQ(faces.size(), reference.surface.triangles.size());
  for (int frame = 1; frame <= 4; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "jelly_%04d.obj", frame);
    ASSERT_TRUE(fs::exists(mesh / name)) << name;
    // One "v" per surface particle (3^3 - 1), and the same faces over the same positions and UVs, every frame.
    EXPECT_EQ(linesStartingWith(mesh / name, "v ").size(), 26u) << name;
    EXPECT_EQ(faceCorners(mesh / name), faces) << name;

    Assimp::Importer importer;
    const aiScene* s = importer.ReadFile((mesh / name).string(), aiProcess_JoinIdenticalVertices);
    ASSERT_TRUE(s && s->mNumMeshes == 1) << importer.GetErrorString();
    const aiMesh* m = s->mMeshes[0];
    EXPECT_EQ(m->mNumVertices, reference.surface.vertexCount());
    EXPECT_EQ(m->mNumFaces, reference.surface.triangles.size());
    ASSERT_TRUE(m->HasTextureCoords(0) && m->HasNormals());
    std::set<std::pair<float, float>> uvs, expected_uvs;
    for (unsigned i = 0; i < m->mNumVertices; ++i) uvs.insert({m->mTextureCoords[0][i].x, m->mTextureCoords[0][i].y});
    for (const auto& uv : reference.surface.uv) expected_uvs.insert({uv.x(), uv.y()});
    EXPECT_EQ(uvs, expected_uvs);
    aiString texture;
    ASSERT_EQ(s->mMaterials[m->mMaterialIndex]->GetTexture(aiTextureType_DIFFUSE, 0, &texture), AI_SUCCESS);
    EXPECT_STREQ(texture.C_Str(), "cat.png");  // relative, next to the .obj
  }
  EXPECT_TRUE(fs::exists(mesh / "cat.png"));
  EXPECT_FALSE(fs::exists(mesh / "jelly_0005.obj"));
  EXPECT_FALSE(fs::exists(mesh / ".partial"));  // frames are exported in memory: no staging folder left
  // The first frame is the initial state: the lowest vertex at 0.6 - 0.5.
  Assimp::Importer importer;
  const aiMesh* first = importer.ReadFile((mesh / "jelly_0001.obj").string(), 0)->mMeshes[0];
  float lowest = 1e9f;
  for (unsigned i = 0; i < first->mNumVertices; ++i) lowest = std::min(lowest, first->mVertices[i].y);
  EXPECT_NEAR(lowest, 0.1f, 1e-6);
}

TEST_F(Run, RunJsonReportsTheRun) {
  const RunReport r = runScene(options(scene()));
  const auto j = nlohmann::json::parse(slurp(dir() / "out/run.json"));
  EXPECT_EQ(j["integrator"], "rk4");
  EXPECT_EQ(j["dt"], 0.002);
  EXPECT_EQ(j["steps"], 75);  // 3 frames of 0.05 s at 0.002
  EXPECT_NEAR(j["simulated_time"].get<double>(), 0.15, 1e-12);
  EXPECT_EQ(j["blew_up"], false);
  EXPECT_EQ(j["gained_energy"], false);  // the energy check (docs/energy.md) passes an ordinary run
  EXPECT_FALSE(j.contains("energy_gain"));
  EXPECT_EQ(j["energy"]["collider_work"], 0.0);  // a static floor does no work
  EXPECT_TRUE(j["wall_time_seconds"].contains("simulate") && j["wall_time_seconds"].contains("export"));
  // Start energy: 27 particles at rest, E = -sum m g.x = 27 * 9.8 * 0.6 (springs at rest).
  EXPECT_NEAR(j["energy"]["start"].get<double>(), 27 * 9.8 * 0.6, 1e-9);
  EXPECT_LT(j["energy"]["end"].get<double>(), j["energy"]["start"].get<double>());  // dampers and the floor dissipate
  EXPECT_NEAR(j["max_speed"].get<double>(), r.max_speed, 1e-12);
  EXPECT_GT(r.max_speed, 0.9);  // it fell 0.1 m before touching: sqrt(2 g 0.09)
}

TEST_F(Run, FrameRangeWritesOnlyThoseFrames) {
  RunOptions o = options(scene());
  o.frames = "2:3";
  const RunReport r = runScene(o);
  EXPECT_EQ(r.frames_written, 2);
  EXPECT_FALSE(fs::exists(dir() / "out/mesh/jelly_0001.obj"));
  EXPECT_TRUE(fs::exists(dir() / "out/mesh/jelly_0002.obj"));
  EXPECT_TRUE(fs::exists(dir() / "out/mesh/jelly_0003.obj"));
  EXPECT_FALSE(fs::exists(dir() / "out/mesh/jelly_0004.obj"));
  for (const char* bad : {"0:2", "3:2", "1:5", "x", "2:"}) {
    o.frames = bad;
    EXPECT_THROW(runScene(o), InputError) << bad;
  }
}

TEST_F(Run, SameSceneGivesTheSameBytes) {
  RunOptions o = options(scene());
  runScene(o);
  const std::string first = slurp(dir() / "out/mesh/jelly_0004.obj");
  o.out = dir() / "again";
  runScene(o);
  EXPECT_EQ(slurp(dir() / "again/mesh/jelly_0004.obj"), first);
}

TEST_F(Run, TwoBodiesInOneScene) {
  RunOptions o = options(scene("\n[bodies.second]\ntype = \"jelly\"\nn = 2\ncenter = [3, 2, 0]\n"));
  const RunReport r = runScene(o);
  ASSERT_FALSE(r.blow_up);
  EXPECT_TRUE(fs::exists(dir() / "out/mesh/jelly_0004.obj"));
  EXPECT_TRUE(fs::exists(dir() / "out/mesh/second_0004.obj"));
  EXPECT_EQ(linesStartingWith(dir() / "out/mesh/second_0004.obj", "v ").size(), 8u);
  const auto j = nlohmann::json::parse(slurp(dir() / "out/run.json"));
  EXPECT_EQ(j["particles"], 27 + 8);
}

TEST_F(Run, BlowUpStopsAtOnceAndKeepsEarlierFrames) {
  // ks 1e6 with dt 0.002: omega h ~ 2.8 for the stiffest modes, far past explicit Euler's limit.
  RunOptions o = options(scene());
  o.integrator = "explicit-euler";
  o.sets = {"jelly.ks=1e6", "simulation.duration=2"};
  const RunReport r = runScene(o);
  ASSERT_TRUE(r.blow_up);
  EXPECT_GT(r.frames_written, 0);
  EXPECT_EQ(r.steps, r.blow_up->step);
  for (int f = 1; f <= r.frames_written; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "jelly_%04d.obj", f);
    EXPECT_TRUE(fs::exists(dir() / "out/mesh" / name));
  }
  const auto j = nlohmann::json::parse(slurp(dir() / "out/run.json"));
  EXPECT_EQ(j["blew_up"], true);
  EXPECT_NE(j["blow_up"]["message"].get<std::string>().find("explicit-euler"), std::string::npos);
}

TEST_F(Run, EnergyGainStopsTheRunAndSaysSo) {
  // The blow-up case above with a frame per step, so the energy is checked at every step: explicit Euler far past its
  // limit passes the energy margin (10% of 159 J) long before a particle reaches |v| = 1000.
  RunOptions o = options(scene());
  o.integrator = "explicit-euler";
  o.sets = {"jelly.ks=1e6", "simulation.fps=500"};
  const RunReport r = runScene(o);
  ASSERT_TRUE(r.energy_gain);
  EXPECT_FALSE(r.blow_up);
  EXPECT_GT(r.frames_written, 0);
  EXPECT_EQ(r.steps, r.energy_gain->step);  // stopped there
  const auto j = nlohmann::json::parse(slurp(dir() / "out/run.json"));
  EXPECT_EQ(j["gained_energy"], true);
  EXPECT_EQ(j["blew_up"], false);
  EXPECT_EQ(j["energy_gain"]["step"], r.steps);
  EXPECT_GT(j["energy_gain"]["gained"].get<double>(), j["energy_gain"]["margin"].get<double>());
  EXPECT_NEAR(j["energy_gain"]["margin"].get<double>(), 0.1 * 27 * 9.8 * 0.6, 1e-9);
  const std::string message = j["energy_gain"]["message"];
  for (const char* part : {"gained energy", "explicit-euler", "--dt", "backward-euler", "restitution"})
    EXPECT_NE(message.find(part), std::string::npos) << part << " missing from: " << message;
}

// The binary itself: exit statuses, nothing written on bad input, --help.
int runBinary(const std::string& arguments, const fs::path& log) {
  const std::string command = std::string(WOBBLE_BINARY) + " " + arguments + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST_F(Run, BinaryExitStatuses) {
  const fs::path file = scene(R"(
[render]
png = false
)"),
                 log = dir() / "log.txt";
  EXPECT_EQ(runBinary("run " + file.string() + " --out " + (dir() / "good").string(), log), 0) << slurp(log);
  EXPECT_TRUE(fs::exists(dir() / "good/mesh/jelly_0004.obj"));

  EXPECT_EQ(runBinary("run " + file.string() + " --dt -1 --out " + (dir() / "bad").string(), log), 2);
  EXPECT_NE(slurp(log).find("simulation.dt = -1"), std::string::npos) << slurp(log);
  EXPECT_FALSE(fs::exists(dir() / "bad"));  // nothing written

  EXPECT_EQ(runBinary("run " + file.string() + " --integrator rk5 --out " + (dir() / "bad").string(), log), 2);
  EXPECT_FALSE(fs::exists(dir() / "bad"));

  EXPECT_EQ(runBinary("run " + file.string() +
                          " --integrator explicit-euler --set jelly.ks=1e6 --set "
                          "simulation.duration=2 --out " +
                          (dir() / "boom").string(),
                      log),
            3);
  EXPECT_NE(slurp(log).find("blew up"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir() / "boom/mesh/jelly_0001.obj"));

  EXPECT_EQ(runBinary("run " + file.string() +
                          " --integrator explicit-euler --set jelly.ks=1e6 --set simulation.fps=500 --out " +
                          (dir() / "gain").string(),
                      log),
            3);
  EXPECT_NE(slurp(log).find("gained energy: integrator explicit-euler, step "), std::string::npos) << slurp(log);
  EXPECT_TRUE(fs::exists(dir() / "gain/mesh/jelly_0001.obj"));

  EXPECT_EQ(runBinary("run --help", log), 0);
  for (const char* option : {"--integrator", "--dt", "--frames", "--out", "--set", "Example"})
    EXPECT_NE(slurp(log).find(option), std::string::npos) << option;
}

}  // namespace
}  // namespace wobble
