#include "app/study/study_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "app/output/progress.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "app/scene/scene_flags.h"
#include "app/study/order_fit.h"
#include "app/view/frame_view.h"
#include "app/view/render_scene.h"
#include "image/image_error.h"
#include "image/pfm_io.h"
#include "image/png_io.h"
#include "io/content_hash.h"
#include "io/text_table.h"
#include "render/denoiser.h"
#include "render/renderer.h"
#include "render/scene_export.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Bumped whenever the renderer's converged picture changes, so cached references of older builds are not reused.
constexpr int kRendererVersion = 6;
// The second half of the reference uses this seed offset: far from any frame number.
constexpr std::uint32_t kSecondHalfSeed = 0x80000000u;

// scene_sky: the scene's own render.sky_sampling (on with an environment map), which a variant can only add to.
render::RenderSettings settingsFor(const RenderVariant& v, int spp, double threshold, int bounces, int frame,
                                   bool motion_blur, bool scene_sky) {
  render::RenderSettings s;
  s.motion_blur = motion_blur;
  s.samples_per_pixel = spp;
  s.max_bounces = v.bounces >= 0 ? v.bounces : bounces;
  render::parseSamplerKind(v.sampler, s.sampler);
  s.sample_sky = v.sky_sampling || scene_sky;
  s.mis = v.mis;
  s.roulette = v.roulette;
  s.noise_threshold = v.adaptive ? static_cast<float>(threshold) : 0.0f;
  s.min_samples = v.adaptive ? 1 : 0;
  s.frame = static_cast<std::uint32_t>(frame);
  return s;
}

void check(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

}  // namespace

const std::vector<RenderVariant>& renderStudyVariants() {
  static const std::vector<RenderVariant> variants = {
      {"independent-nomis",
       "independent random samples, no MIS (suns and area lights by light sampling alone), no denoising", "independent",
       false, false, false, -1, false},
      {"independent", "independent random samples, no denoising", "independent"},
      {"sobol", "Owen-scrambled Sobol samples, no denoising", "sobol"},
      {"sobol+sky", "Sobol, with next-event estimation of the sky (MIS), no denoising", "sobol", true},
      {"independent+denoise", "independent samples, denoised", "independent", false, true},
      {"sobol+denoise", "Sobol samples, denoised", "sobol", false, true},
      {"adaptive", "Sobol, adaptive sampling (4 to max spp) over noise thresholds, no denoising", "sobol", false, false,
       true},
      {"adaptive+denoise", "Sobol, adaptive sampling over noise thresholds, denoised", "sobol", false, true, true},
      {"sobol+denoise-rr", "Sobol samples, denoised, Russian roulette by throughput from the second continuation on",
       "sobol", false, true, false, -1, true, true},
      {"sobol+denoise-1bounce", "Sobol samples, denoised, one bounce fewer than the reference (at most 1)", "sobol",
       false, true, false, 1},
  };
  return variants;
}

std::vector<RenderVariantFit> fitRenderStudy(const std::vector<RenderPoint>& points, double floor) {
  std::vector<RenderVariantFit> fits;
  for (const RenderVariant& v : renderStudyVariants()) {
    std::vector<double> spp, rmse;
    for (const RenderPoint& p : points)
      if (p.variant == v.name && p.rmse > 2 * floor) spp.push_back(p.mean_spp), rmse.push_back(p.rmse);
    const bool present =
        std::any_of(points.begin(), points.end(), [&](const RenderPoint& p) { return p.variant == v.name; });
    if (present) fits.push_back({v.name, fitOrder(spp, rmse), int(spp.size())});
  }
  return fits;
}

RenderStudyResult runRenderStudy(const RenderStudyOptions& o) {
  check(o.reference_spp >= 2 && o.reference_spp <= 1 << 20 && o.reference_spp % 2 == 0,
        "--reference-spp " + std::to_string(o.reference_spp) + ": must be even, in [2, 1048576]");
  check(o.max_spp >= 1 && o.max_spp <= 65536, "--max-spp " + std::to_string(o.max_spp) + ": must be in [1, 65536]");
  check(o.repeats >= 1 && o.repeats <= 100, "--repeats " + std::to_string(o.repeats) + ": must be in [1, 100]");
  for (double t : o.thresholds)
    check(t > 0 && t <= 1, "--thresholds " + io::formatNumber(t) + ": each must be in (0, 1]");
  std::vector<RenderVariant> variants;
  for (const std::string& name : o.variants) {
    const auto& all = renderStudyVariants();
    const auto it = std::find_if(all.begin(), all.end(), [&](const RenderVariant& v) { return v.name == name; });
    if (it == all.end()) {
      std::string allowed;
      for (const RenderVariant& v : all) allowed += (allowed.empty() ? "" : ", ") + v.name;
      throw InputError("--variants " + name + ": unknown variant (allowed: " + allowed + ")");
    }
    variants.push_back(*it);
  }
  if (variants.empty()) variants = renderStudyVariants();

  RenderFlags flags;
  flags.resolution = o.resolution;
  const SceneFile scene = loadScene(o.scene, o.sets, renderFlagSettings(flags));
  const int frame = o.frame > 0 ? o.frame : (scene.frameCount() + 1) / 2;
  check(frame <= scene.frameCount(),
        "--frame " + std::to_string(frame) + ": the scene has " + std::to_string(scene.frameCount()) + " frames");

  RenderStudyResult result;
  result.scene_name = scene.name;
  result.scene_file = o.scene;
  result.frame = frame;
  result.width = scene.render.camera.resolution[0];
  result.height = scene.render.camera.resolution[1];
  result.bounces = scene.render.options.bounces;
  result.reference_spp = o.reference_spp;
  const fs::path out = o.out.empty() ? fs::path("out") / ("study-render-" + scene.name) : o.out;
  fs::create_directories(out / "images");

  const FrameView view = simulateTo(scene, frame);
  const render::Camera camera(view.camera);
  render::exportScene(view.scene.scene(), camera, out / "frame");
  image::ToneMap tone;
  tone.exposure = static_cast<float>(scene.render.options.exposure);
  const int w = result.width, h = result.height;

  int total = 2;
  for (const RenderVariant& v : variants)
    total += v.adaptive ? int(o.thresholds.size()) : int(std::log2(o.max_spp)) + 1;
  Progress progress("render study " + scene.name, total, "render");
  int done = 0;
  const auto tick = [&] {
    if (o.progress) progress.update(++done);
  };

  // The reference: two halves with independent seeds; cached.
  std::ostringstream key;
  key << scene.text << "\nframe " << frame << " bounces " << result.bounces << " spp " << o.reference_spp << " version "
      << kRendererVersion;
  if (const EnvironmentConfig& env = scene.render.options.environment; env.named()) {  // its pixels, not its name
    io::ContentHash file;
    file.addFile(env.file);
    key << " environment " << file.hex();
  }
  const bool scene_sky = scene.render.options.sky_sampling;
  const std::string hex = io::hashOf(key.str());  // stable across builds, unlike std::hash
  result.reference_file = out / ("reference-" + hex + ".pfm");
  const fs::path second_half = out / ("reference-" + hex + "-b.pfm");
  std::vector<image::Color> reference, half_b;
  if (fs::exists(result.reference_file) && fs::exists(second_half)) {
    image::FloatImage a = image::readPfm(result.reference_file), b = image::readPfm(second_half);
    if (a.width == w && a.height == h && b.width == w && b.height == h) {
      reference = std::move(a.pixels);
      half_b = std::move(b.pixels);
      result.reference_cached = true;
      done += 2;
    }
  }
  if (!result.reference_cached) {
    const RenderVariant sobol{"reference", "", "sobol"};
    const auto start = Clock::now();
    image::Film a =
        render::render(view.scene.scene(), camera,
                       settingsFor(sobol, o.reference_spp / 2, 0, result.bounces, frame, view.motion_blur, scene_sky));
    tick();
    image::Film b = render::render(view.scene.scene(), camera,
                                   settingsFor(sobol, o.reference_spp / 2, 0, result.bounces, frame ^ kSecondHalfSeed,
                                               view.motion_blur, scene_sky));
    tick();
    result.reference_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    reference = std::move(a.color);
    half_b = std::move(b.color);
    // Stored as its two halves: the first file holds half a, completed below to the mean before use.
    image::writePfm(second_half, w, h, half_b);
    image::writePfm(result.reference_file, w, h, reference);
  }
  const image::ImageError halves = image::imageError(w, h, reference, half_b, tone);
  for (std::size_t i = 0; i < reference.size(); ++i) reference[i] = 0.5f * (reference[i] + half_b[i]);
  result.reference_rmse = halves.rmse / 2;
  image::writePng(out / "reference.png", image::develop(w, h, reference, tone));

  for (const RenderVariant& v : variants) {
    std::vector<std::pair<int, double>> sweep;  // (spp, threshold)
    if (v.adaptive)
      for (double t : o.thresholds) sweep.emplace_back(o.max_spp, t);
    else
      for (int spp = 1; spp <= o.max_spp; spp *= 2) sweep.emplace_back(spp, 0.0);
    for (const auto& [spp, threshold] : sweep) {
      RenderPoint p;
      p.variant = v.name;
      p.spp = spp;
      p.threshold = threshold;
      p.seconds = p.denoise_seconds = std::numeric_limits<double>::infinity();
      std::vector<image::Color> image;
      render::RenderStats stats;
      for (int r = 0; r < o.repeats; ++r) {
        const auto start = Clock::now();
        image::Film film =
            render::render(view.scene.scene(), camera,
                           settingsFor(v, spp, threshold, result.bounces, frame, view.motion_blur, scene_sky), &stats);
        const auto rendered = Clock::now();
        image = v.denoise ? render::denoise(film) : std::move(film.color);
        const auto end = Clock::now();
        p.seconds = std::min(p.seconds, std::chrono::duration<double>(end - start).count());
        p.denoise_seconds = std::min(p.denoise_seconds, std::chrono::duration<double>(end - rendered).count());
      }
      if (!v.denoise) p.denoise_seconds = 0;
      p.mean_spp = double(stats.camera_rays) / double(std::size_t(w) * h);
      p.rays_per_sample = double(stats.rays) / double(stats.camera_rays);
      const image::ImageError e = image::imageError(w, h, image, reference, tone);
      p.rmse = e.rmse, p.relmse = e.relmse, p.worst_tile_rmse = e.worst_tile_rmse,
      p.worst_tile_relmse = e.worst_tile_relmse;
      std::string file = v.name + "_" +
                         (v.adaptive ? std::string("t") + io::formatNumber(threshold, 3) : std::to_string(spp)) +
                         ".png";
      std::replace(file.begin(), file.end(), '+', '-');
      image::writePng(out / "images" / file, image::develop(w, h, image, tone));
      result.points.push_back(p);
      tick();
    }
  }
  progress.finish();
  result.fits = fitRenderStudy(result.points, result.reference_rmse);
  return result;
}

}  // namespace wobble
