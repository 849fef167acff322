// A run folder stands alone (app/output/carried_scene.h): the scene as resolved and every file it reads (model,
// texture, collider model, environment map) travel inside OUT/scene, run.json names them relative to the folder, and
// `wobble render OUT`, `blend OUT`, `video OUT` and `frames OUT` work from / after the folder has moved and the project
// it was made from is gone, a re-rendered frame the bytes of the original. A carried file altered or removed: exit 2
// naming it, nothing written.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "app/output/external_program.h"
#include "image/image_file.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using testing::runWobble;
using testing::slurpFile;

class RunFolder : public testing::ScratchDir {
 protected:
  // `wobble ARGS` run from `cwd`.
  int runFrom(const fs::path& cwd, const std::string& arguments, const fs::path& log) {
    const int status = std::system(
        ("cd " + cwd.string() + " && " + WOBBLE_BINARY + " " + arguments + " > " + log.string() + " 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  // A copy of the project's jelly_mould scene (a mesh jelly, textured, on a mesh plate) with an environment map.
  fs::path makeProject() {
    const fs::path project = dir() / "project", scenes = project / "scenes";
    fs::create_directories(scenes);
    fs::copy(testing::sourceDir() / "scenes/models", scenes / "models", fs::copy_options::recursive);
    fs::create_directories(scenes / "textures");
    fs::copy_file(testing::sourceDir() / "scenes/textures/cat.png", scenes / "textures/cat.png");
    fs::copy_file(testing::sourceDir() / "scenes/jelly_mould.toml", scenes / "jelly_mould.toml");
    image::ImageF sky(16, 8, 3);
    for (std::size_t i = 0; i < sky.pixels.size(); ++i) sky.pixels[i] = 0.2f + 0.01f * float(i % 37);
    image::writeExrImage(scenes / "sky.exr", sky, {"R", "G", "B"}, false);
    return project;
  }
  static std::string runArgs(const std::string& out) {
    return "run scenes/jelly_mould.toml --out " + out +
           " --set simulation.duration=0.1 --set 'render.environment=\"sky.exr\"' --set jelly.cells=4 "
           "--resolution 48x27 --spp 2 --render png";
  }
};

TEST_F(RunFolder, MovedFolderRendersAndBlendsFromRootWithTheProjectGone) {
  const fs::path project = makeProject(), log = dir() / "log.txt";
  ASSERT_EQ(runFrom(project, runArgs("out/mould"), log), 0) << slurpFile(log);
  const fs::path made = project / "out/mould";

  // run.json: the carried scene and files, relative to the folder.
  const nlohmann::json j = nlohmann::json::parse(slurpFile(made / "run.json"));
  EXPECT_EQ(j.at("scene"), "scene/jelly_mould.toml");
  std::set<std::string> carried;
  for (const auto& c : j.at("carried")) {
    const std::string path = c.at("path");
    carried.insert(fs::path(path).filename().string());
    EXPECT_FALSE(fs::path(path).is_absolute()) << path;
    EXPECT_TRUE(fs::is_regular_file(made / path)) << path;
  }
  EXPECT_EQ(carried, (std::set<std::string>{"jelly_mould.toml", "jelly_mould.obj", "cat.png", "plate.obj", "sky.exr"}));

  // The original: frame 2 re-rendered in place, from the project.
  ASSERT_EQ(runFrom(project, "render out/mould --frames 2", log), 0) << slurpFile(log);
  const std::string original = slurpFile(made / "frames/jelly_mould_0002.png");
  ASSERT_FALSE(original.empty());
  EXPECT_EQ(original, slurpFile(made / "frames/jelly_mould_0002.png"));

  // Moved, the project deleted, every command from /.
  const fs::path moved = dir() / "elsewhere/mould";
  fs::create_directories(moved.parent_path());
  fs::rename(made, moved);
  fs::remove_all(project);
  fs::remove(moved / "frames/jelly_mould_0002.png");
  ASSERT_EQ(runFrom("/", "render " + moved.string() + " --frames 2", log), 0) << slurpFile(log);
  EXPECT_TRUE(slurpFile(moved / "frames/jelly_mould_0002.png") == original) << "the re-rendered frame differs";
  ASSERT_EQ(runFrom("/", "render " + (moved / "mesh").string() + " --frames 3", log), 0) << slurpFile(log);
  ASSERT_EQ(runFrom("/", "frames " + moved.string() + " --chunks 2", log), 0) << slurpFile(log);
  EXPECT_EQ(slurpFile(log), "1:2\n3:3\n");
  if (findProgram("ffmpeg")) {
    EXPECT_EQ(runFrom("/", "video " + moved.string(), log), 0) << slurpFile(log);
    EXPECT_TRUE(fs::is_regular_file(moved / "jelly_mould.mp4"));
  }
  if (findProgram("blender")) {
    EXPECT_EQ(runFrom("/", "blend " + moved.string(), log), 0) << slurpFile(log);
    EXPECT_TRUE(fs::is_regular_file(moved / "jelly_mould.blend"));
  } else {
    std::cout << "blender is not on PATH: wobble blend from / not checked\n";
  }
}

TEST_F(RunFolder, AlteredOrRemovedCarriedFileIsRefusedNamingIt) {
  const fs::path project = makeProject(), log = dir() / "log.txt";
  ASSERT_EQ(runFrom(project, runArgs("out/mould") + " --frames 1:2", log), 0) << slurpFile(log);
  const fs::path out = project / "out/mould";
  fs::path texture;
  for (const auto& e : fs::recursive_directory_iterator(out / "scene"))
    if (e.path().filename() == "cat.png") texture = e.path();
  ASSERT_FALSE(texture.empty());
  const std::string frame = slurpFile(out / "frames/jelly_mould_0001.png");
  { std::ofstream(texture, std::ios::app) << "x"; }
  EXPECT_EQ(runFrom("/", "render " + out.string(), log), 2) << slurpFile(log);
  EXPECT_NE(slurpFile(log).find(texture.string() + ": altered since the run"), std::string::npos) << slurpFile(log);
  EXPECT_EQ(slurpFile(out / "frames/jelly_mould_0001.png"), frame) << "written despite the error";
  fs::remove(texture);
  EXPECT_EQ(runFrom("/", "render " + out.string(), log), 2) << slurpFile(log);
  EXPECT_NE(slurpFile(log).find(texture.string() + ": missing"), std::string::npos) << slurpFile(log);
  EXPECT_EQ(runFrom("/", "blend " + out.string(), log), 2) << slurpFile(log);
  EXPECT_NE(slurpFile(log).find(texture.string() + ": missing"), std::string::npos) << slurpFile(log);
  const std::string scene = slurpFile(out / "scene/jelly_mould.toml");
  { std::ofstream(out / "scene/jelly_mould.toml") << scene << "# edited\n"; }
  EXPECT_EQ(runFrom("/", "render " + out.string(), log), 2) << slurpFile(log);
  EXPECT_NE(slurpFile(log).find("jelly_mould.toml: altered since the run"), std::string::npos) << slurpFile(log);
  EXPECT_FALSE(fs::exists(out / "frames/jelly_mould_0002.png.tmp"));
}

}  // namespace
}  // namespace wobble
