// The README's first command (the default scene) frame by frame, stage by stage: one 1280x720 frame of a shipped scene
// at the scene's own render settings (final quality), as `wobble run` renders it.
//   BM_Render    render(): path tracing (all threads)
//   BM_Denoise   denoise() of that film (all threads)
//   BM_Develop   tone mapping to 8-bit sRGB (one thread, as the run's writer)
//   BM_Png       PNG encoding and writing (one thread, as the run's writer)
// Argument: the frame (default scene jelly_slope; WOBBLE_BENCH_SCENE=path picks another). Frames 30, 150 and 270
// show the jelly landing, mid-slide with much floor in view, and far down the slope. A frame's total is what the
// run spends on it (the writer overlaps the next frame's render, so the run's wall time is a little less).
// Run: build/frame_bench (from the project root: the scene's paths are relative to it).
#include <malloc.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>

#include <benchmark/benchmark.h>

#include "app/pictures/frame_view.h"
#include "app/scene/render_config.h"
#include "app/scene/scene_file.h"
#include "image/png_io.h"
#include "render/denoiser.h"
#include "render/renderer.h"

namespace {

using namespace wobble;

struct Prepared {
  SceneFile scene;
  FrameView view;
  image::Film film;
  std::vector<image::Color> denoised;
};

Prepared& prepared(int frame) {
  static const bool heap = [] {  // as app/main.cpp: large per-frame buffers reuse heap memory, no fresh pages
    mallopt(M_MMAP_THRESHOLD, 512 << 20);
    return mallopt(M_TRIM_THRESHOLD, 1 << 30);
  }();
  (void)heap;
  static std::map<int, std::unique_ptr<Prepared>> cache;
  auto& p = cache[frame];
  if (!p) {
    const char* file = std::getenv("WOBBLE_BENCH_SCENE");
    SceneFile scene = loadScene(file ? file : "scenes/jelly_slope.toml");
    FrameView view = simulateTo(scene, frame);
    p = std::make_unique<Prepared>(Prepared{std::move(scene), std::move(view), {}, {}});
    render::RenderSettings settings = renderSettings(p->scene.render.options, frame);
    settings.motion_blur = p->view.motion_blur;
    p->film = render::render(p->view.scene.scene(), render::Camera(p->view.camera), settings);
    p->denoised = render::denoise(p->film);
  }
  return *p;
}

void BM_Render(benchmark::State& state) {
  Prepared& p = prepared(int(state.range(0)));
  const render::Camera camera(p.view.camera);
  render::RenderSettings settings = renderSettings(p.scene.render.options, int(state.range(0)));
  settings.motion_blur = p.view.motion_blur;
  render::RenderStats stats;
  for (auto _ : state) benchmark::DoNotOptimize(render::render(p.view.scene.scene(), camera, settings, &stats));
  state.counters["rays_per_pixel"] = double(stats.rays) / double(p.film.color.size());
}

void BM_Denoise(benchmark::State& state) {
  Prepared& p = prepared(int(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(render::denoise(p.film));
}

void BM_Develop(benchmark::State& state) {
  Prepared& p = prepared(int(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(image::develop(p.film.width, p.film.height, p.denoised));
}

void BM_Png(benchmark::State& state) {
  Prepared& p = prepared(int(state.range(0)));
  const image::Image8 image = image::develop(p.film.width, p.film.height, p.denoised);
  const auto file = std::filesystem::temp_directory_path() / "wobble_frame_bench.png";
  for (auto _ : state) image::writePng(file, image);
  std::filesystem::remove(file);
}

BENCHMARK(BM_Render)->Arg(30)->Arg(150)->Arg(270)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Denoise)->Arg(30)->Arg(150)->Arg(270)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Develop)->Arg(150)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Png)->Arg(150)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
