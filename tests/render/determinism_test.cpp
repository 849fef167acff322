// Determinism: the same scene, frame and sample count give the same bytes whatever the thread count and tiling, at
// several samples per pixel and on the one-sample path (the default quality's: its own sampler and an unfilled film,
// renderer.cpp). A test-only observer of TBB's arena (tests/threads_seen.h) checks that render() woke a second thread.
// (With the tile loop made serial on purpose, the one-sample test fails; at four samples a worker still joins for the
// film's parallel fill, which the observer cannot tell from the tiles.)
#include <cstring>
#include <memory>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "image/film.h"
#include "render/image_texture.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "tests/threads_seen.h"

namespace wobble::render {
namespace {

// A small version of a real scene: textured jelly-like mesh (a folded sheet with vertex normals), wooden slope,
// a box platform, a sphere, a sun, an area light and the sky, or (lit) an environment map with a bright spot instead.
// blur: the sheet, slope, platform and ball move over the shutter (several poses each, as a run gives them).
Scene demoScene(bool blur = false, bool lit = false) {
  Scene scene;
  std::vector<Color> texels;
  for (int i = 0; i < 64; ++i) texels.emplace_back((i % 8) / 8.0f, (i / 8) / 8.0f, 0.3f);
  const auto picture = std::make_shared<ImageTexture>(8, 8, texels);
  const auto jelly = scene.addMaterial(Material::jelly("jelly", Color(1, 0.9f, 0.9f), picture));
  const auto wood = scene.addMaterial(Material::textured("wood", std::make_shared<WoodTexture>()));
  const auto grey = scene.addMaterial(Material::diffuse("grey", Color::Constant(0.6f)));

  TriangleMesh sheet;
  sheet.name = "sheet";
  const int n = 6;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float u = i / float(n - 1), v = j / float(n - 1);
      sheet.positions.emplace_back(u * 2 - 1, 1 + 0.5f * std::sin(3 * u), v * 2 - 1);
      sheet.normals.emplace_back(Eigen::Vector3f(-1.5f * std::cos(3 * u), 1, 0).normalized());
      sheet.uv.emplace_back(u, v);
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      sheet.triangles.push_back({a, a + n, a + 1});
      sheet.triangles.push_back({a + 1, a + n, a + n + 1});
    }
  const ShapeId sheet_id = scene.addMesh(sheet, jelly);
  const ShapeId slope = scene.addQuad("slope", Quad{{0, 0, 0}, {0.2f, 1, 0}, 8, 1}, wood);
  const ShapeId platform = scene.addBox("platform", Box{{2, 0.3f, 1}, {1, 0.3f, 1}}, grey);
  const ShapeId ball = scene.addSphere("ball", Sphere{{-1.5f, 0.7f, 1}, 0.5f}, grey);
  if (blur) {
    std::vector<std::vector<Eigen::Vector3f>> sheet_poses;
    std::vector<Scene::MeshPose> poses;
    std::vector<Quad> quads;
    std::vector<Box> boxes;
    std::vector<Sphere> spheres;
    for (int j = 0; j < 4; ++j) {
      const Eigen::Vector3f shift(0.15f * j, 0.05f * j * j, 0);
      sheet_poses.push_back(sheet.positions);
      for (auto& p : sheet_poses.back()) p += shift;
      quads.push_back(Quad{{0, -0.05f * j, 0}, {0.2f, 1, 0.02f * j}, 8, 1});
      boxes.push_back(Box{{2 - 0.2f * j, 0.3f, 1}, {1, 0.3f, 1}});
      spheres.push_back(Sphere{{-1.5f, 0.7f + 0.2f * j, 1}, 0.5f});
    }
    for (const auto& p : sheet_poses) poses.push_back({p, sheet.normals});
    scene.updateMeshMotion(sheet_id, poses);
    scene.updateQuadMotion(slope, quads);
    scene.updateBoxMotion(platform, boxes);
    scene.updateSphereMotion(ball, spheres);
  }
  scene.lights.suns = {SunLight{}};
  scene.lights.rects = {RectLight{}};
  if (lit) {
    image::ImageF map(32, 16, 3);
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x)
        for (int k = 0; k < 3; ++k) map.at(x, y, k) = (x == 9 && y == 4) ? 500.0f : 0.2f + 0.05f * float((x + k) % 4);
    scene.lights.environment = std::make_shared<EnvironmentMap>(map, 40, 1.5f);
  }
  scene.commit();
  return scene;
}

struct Frame {
  image::Film film;
  image::Image8 image;
  int other_threads = 0;  // threads besides the caller's that joined TBB's parallel work
};

Frame renderWithThreads(int threads, int tile_size = 16, std::uint32_t frame = 0, int spp = 4, bool blur = false,
                        bool lit = false) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  const Scene scene = demoScene(blur, lit);  // built under the same limit: the BVH build is part of the result
  CameraParams cp;
  cp.position = {0, 3, 6};
  cp.look_at = {0, 0.8f, 0};
  cp.width = 48;
  cp.height = 32;
  RenderSettings settings;
  settings.samples_per_pixel = spp;
  settings.tile_size = tile_size;
  settings.frame = frame;
  settings.motion_blur = blur;
  if (blur) cp.shutter_motion = {0.3f, 0, -0.2f};
  settings.sample_sky = lit;
  auto seen = std::make_unique<wobble::testing::ThreadsSeen>();  // render()'s threads only (not the BVH build's)
  image::Film film = render(scene, Camera(cp), settings);
  const int other_threads = seen->others();
  seen.reset();
  image::Image8 image = image::develop(film);
  return {std::move(film), std::move(image), other_threads};
}

// On two threads, until a second thread took part in the render (a small frame may be done before a worker wakes
// on a busy machine, where a try can take 3 ms; 200 tries at most): every try must give the same bytes, returned
// with its thread count.
Frame renderOnTwoThreads(int tile_size = 16, std::uint32_t frame = 0, int spp = 4, bool blur = false,
                         bool lit = false) {
  Frame first = renderWithThreads(2, tile_size, frame, spp, blur, lit);
  for (int attempt = 1; attempt < 200 && first.other_threads == 0; ++attempt) {
    const Frame again = renderWithThreads(2, tile_size, frame, spp, blur, lit);
    EXPECT_EQ(again.image.pixels, first.image.pixels) << "try " << attempt;
    first.other_threads = again.other_threads;
  }
  return first;
}

bool sameFloats(const auto& a, const auto& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
}

// One thread and two (a second one seen to take part) give the same picture and layers; the picture is not trivially
// uniform: something in it was lit.
void expectSameBytes(const Frame& one, const Frame& two) {
  EXPECT_EQ(one.other_threads, 0);
  EXPECT_GE(two.other_threads, 1) << "no second thread ran";
  EXPECT_EQ(one.image.pixels, two.image.pixels);
  EXPECT_TRUE(sameFloats(one.film.color, two.film.color));
  EXPECT_TRUE(sameFloats(one.film.diffuse, two.film.diffuse));
  EXPECT_TRUE(sameFloats(one.film.albedo, two.film.albedo));
  EXPECT_TRUE(sameFloats(one.film.normal, two.film.normal));
  EXPECT_TRUE(sameFloats(one.film.depth, two.film.depth));
  EXPECT_EQ(one.film.samples, two.film.samples);
  const auto [lo, hi] = std::minmax_element(one.image.pixels.begin(), one.image.pixels.end());
  EXPECT_GT(*hi - *lo, 100);
}

TEST(Determinism, OneAndTwoThreadsGiveIdenticalBytes) { expectSameBytes(renderWithThreads(1), renderOnTwoThreads()); }

// One sample per pixel: the default quality's path (Independent sampler, film set pixel by pixel as it renders).
TEST(Determinism, OneSamplePathGivesIdenticalBytesOnOneAndTwoThreads) {
  const Frame one = renderWithThreads(1, 16, 0, 1);
  expectSameBytes(one, renderOnTwoThreads(16, 0, 1));
  EXPECT_FALSE(sameFloats(one.film.color, renderWithThreads(2).film.color));  // not the four-sample picture
}

// Motion blur (every shape and the camera moving over the shutter, a time per sample): the same bytes on one and two
// threads and with other tiles, at four samples and at one; and not the still picture.
TEST(Determinism, MotionBlurGivesIdenticalBytesOnOneAndTwoThreadsAndAnyTiling) {
  for (const int spp : {4, 1}) {
    SCOPED_TRACE(std::to_string(spp) + " spp");
    const Frame one = renderWithThreads(1, 16, 0, spp, true);
    expectSameBytes(one, renderOnTwoThreads(16, 0, spp, true));
    EXPECT_TRUE(sameFloats(one.film.color, renderWithThreads(2, 7, 0, spp, true).film.color));
    EXPECT_FALSE(sameFloats(one.film.color, renderWithThreads(1, 16, 0, spp).film.color));
  }
}

// Lit by an environment map, sampled by its luminance (render/environment.h): the same bytes too.
TEST(Determinism, EnvironmentLitFrameGivesIdenticalBytesWhateverTheThreadsAndTiles) {
  const Frame one = renderWithThreads(1, 16, 0, 4, false, true);
  expectSameBytes(one, renderOnTwoThreads(16, 0, 4, false, true));
  EXPECT_TRUE(sameFloats(one.film.color, renderWithThreads(2, 7, 0, 4, false, true).film.color));
  EXPECT_FALSE(sameFloats(one.film.color, renderWithThreads(1).film.color));  // not the sky's picture
}

TEST(Determinism, TilingDoesNotMatterButTheFrameIndexDoes) {
  const Frame a = renderWithThreads(2, 16), b = renderWithThreads(2, 7);
  EXPECT_TRUE(sameFloats(a.film.color, b.film.color));
  const Frame next = renderWithThreads(2, 16, 1);
  EXPECT_FALSE(sameFloats(a.film.color, next.film.color));  // new noise pattern each frame
}

}  // namespace
}  // namespace wobble::render
