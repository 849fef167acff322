#include "app/study/study_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/output/progress.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "app/scene/scene_flags.h"
#include "app/study/order_fit.h"
#include "app/pictures/frame_view.h"
#include "app/pictures/render_scene.h"
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

// The frame the study renders, simulated to (built in place: FrameView holds the render scene).
struct Framed {
  Framed(const SceneFile& scene, int frame) : view(simulateTo(scene, frame)), camera(view.camera) {}
  FrameView view;
  render::Camera camera;
};

// A work item's result: its image (float, linear) and what the report needs of its render (farm_pieces.h keeps
// both: the numbers in its .json, the image's floats as its data).
struct Rendered {
  nlohmann::json meta;
  std::vector<image::Color> pixels;
};

std::vector<image::Color> pixelsOf(const std::string& data, int w, int h) {
  const std::size_t count = std::size_t(w) * std::size_t(h);
  if (data.size() != count * sizeof(float) * 3)
    throw InputError("render study pieces: a kept image holds " + std::to_string(data.size()) + " bytes, not the " +
                     std::to_string(count * sizeof(float) * 3) + " of " + std::to_string(w) + " x " +
                     std::to_string(h) + " pixels; run its piece again");
  std::vector<image::Color> pixels(count);
  for (std::size_t i = 0; i < count; ++i) std::memcpy(pixels[i].data(), data.data() + i * sizeof(float) * 3, 12);
  return pixels;
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
  image::ToneMap tone;
  tone.exposure = static_cast<float>(scene.render.options.exposure);
  const int w = result.width, h = result.height;
  const bool scene_sky = scene.render.options.sky_sampling;

  // The reference's cache key; the reference is cached as its two halves, the first file holding half a.
  std::ostringstream key;
  key << scene.text << "\nframe " << frame << " bounces " << result.bounces << " spp " << o.reference_spp << " version "
      << kRendererVersion;
  if (const EnvironmentConfig& env = scene.render.options.environment; env.named()) {  // its pixels, not its name
    io::ContentHash file;
    file.addFile(env.file);
    key << " environment " << file.hex();
  }
  const std::string hex = io::hashOf(key.str());  // stable across builds, unlike std::hash
  result.reference_file = out / ("reference-" + hex + ".pfm");
  const fs::path half_files[2] = {result.reference_file, out / ("reference-" + hex + "-b.pfm")};

  // The work items: the reference's two halves (the first also exports the frame), then every point of the sweep.
  struct Shot {
    RenderVariant variant;
    int spp;
    double threshold;
  };
  std::vector<Shot> shots;
  for (const RenderVariant& v : variants)
    if (v.adaptive)
      for (double t : o.thresholds) shots.push_back({v, o.max_spp, t});
    else
      for (int spp = 1; spp <= o.max_spp; spp *= 2) shots.push_back({v, spp, 0.0});
  std::optional<FarmPieces> pieces;
  if (o.piece || o.gather) {
    std::ostringstream sweep;  // everything a point's image and time depend on, beside the reference's key
    sweep << "wobble study render 1\n" << key.str() << "\nrepeats " << o.repeats;
    for (const Shot& shot : shots) sweep << "\n" << shot.variant.name << " " << shot.spp << " " << shot.threshold;
    pieces.emplace(out, "render", io::hashOf(sweep.str()), 2 + shots.size(), o.gather ? std::nullopt : o.piece);
  }
  std::tie(result.piece.first, result.piece.last) =
      pieces ? pieces->range() : std::pair<std::size_t, std::size_t>{0, 2 + shots.size()};
  result.piece.items = 2 + shots.size();
  std::vector<nlohmann::json> gathered;
  if (o.gather) gathered = pieces->gather();

  Progress progress("render study " + scene.name, o.gather ? 0 : int(result.piece.last - result.piece.first), "render");
  int done = 0;
  std::optional<Framed> framed;  // simulated once, when this command renders something
  const auto view = [&]() -> const Framed& {
    if (!framed) framed.emplace(scene, frame);
    return *framed;
  };
  // Item i rendered: a reference half (from the cache when there) or a point, timed.
  const auto render = [&](std::size_t i) -> Rendered {
    Rendered r;
    if (i < 2) {
      if (i == 0) render::exportScene(view().view.scene.scene(), view().camera, out / "frame");
      if (fs::exists(half_files[i])) {
        image::FloatImage cached = image::readPfm(half_files[i]);
        if (cached.width == w && cached.height == h) {
          r.meta = {{"seconds", 0.0}, {"cached", true}};
          r.pixels = std::move(cached.pixels);
          return r;
        }
      }
      const RenderVariant sobol{"reference", "", "sobol"};
      const auto start = Clock::now();
      const std::uint32_t seed = i == 0 ? std::uint32_t(frame) : std::uint32_t(frame) ^ kSecondHalfSeed;
      image::Film film = render::render(view().view.scene.scene(), view().camera,
                                        settingsFor(sobol, o.reference_spp / 2, 0, result.bounces, int(seed),
                                                    view().view.motion_blur, scene_sky));
      r.meta = {{"seconds", std::chrono::duration<double>(Clock::now() - start).count()}, {"cached", false}};
      r.pixels = std::move(film.color);
      image::writePfm(half_files[i], w, h, r.pixels);
      return r;
    }
    const Shot& shot = shots[i - 2];
    double seconds = std::numeric_limits<double>::infinity(), denoise_seconds = seconds;
    render::RenderStats stats;
    for (int k = 0; k < o.repeats; ++k) {
      const auto start = Clock::now();
      image::Film film = render::render(view().view.scene.scene(), view().camera,
                                        settingsFor(shot.variant, shot.spp, shot.threshold, result.bounces, frame,
                                                    view().view.motion_blur, scene_sky),
                                        &stats);
      const auto rendered = Clock::now();
      r.pixels = shot.variant.denoise ? render::denoise(film) : std::move(film.color);
      const auto end = Clock::now();
      seconds = std::min(seconds, std::chrono::duration<double>(end - start).count());
      denoise_seconds = std::min(denoise_seconds, std::chrono::duration<double>(end - rendered).count());
    }
    r.meta = {{"seconds", seconds},
              {"denoise_seconds", shot.variant.denoise ? denoise_seconds : 0.0},
              {"mean_spp", double(stats.camera_rays) / double(std::size_t(w) * h)},
              {"rays_per_sample", double(stats.rays) / double(stats.camera_rays)}};
    return r;
  };
  // Item i: rendered here (one machine, or this piece's), kept by a piece, or gathered.
  const auto item = [&](std::size_t i) -> std::optional<Rendered> {
    if (o.gather) return Rendered{gathered[i], pixelsOf(pieces->data(i), w, h)};
    if (pieces && pieces->load(i)) {
      ++result.piece.kept;
      return std::nullopt;  // a piece's own item, done by an earlier run of it
    }
    Rendered r = render(i);
    if (o.progress) progress.update(++done);
    if (pieces)
      pieces->store(i, r.meta,
                    std::string_view(reinterpret_cast<const char*>(r.pixels.data()),
                                     sizeof(float) * 3 * r.pixels.size()));
    return r;
  };
  if (o.piece) {  // its own items, kept for the gathering; no errors without the reference
    for (std::size_t i = result.piece.first; i < result.piece.last; ++i) item(i);
    progress.finish();
    return result;
  }

  // The reference: the mean of its halves; their difference estimates its own error.
  Rendered a = *item(0), b = *item(1);
  result.reference_cached = a.meta.at("cached").get<bool>() && b.meta.at("cached").get<bool>();
  result.reference_seconds = a.meta.at("seconds").get<double>() + b.meta.at("seconds").get<double>();
  std::vector<image::Color>& reference = a.pixels;
  const image::ImageError halves = image::imageError(w, h, reference, b.pixels, tone);
  for (std::size_t i = 0; i < reference.size(); ++i) reference[i] = 0.5f * (reference[i] + b.pixels[i]);
  result.reference_rmse = halves.rmse / 2;
  image::writePng(out / "reference.png", image::develop(w, h, reference, tone));

  for (std::size_t i = 0; i < shots.size(); ++i) {
    const Shot& shot = shots[i];
    const Rendered r = *item(2 + i);
    RenderPoint p;
    p.variant = shot.variant.name;
    p.spp = shot.spp;
    p.threshold = shot.threshold;
    p.seconds = r.meta.at("seconds").get<double>();
    p.denoise_seconds = r.meta.at("denoise_seconds").get<double>();
    p.mean_spp = r.meta.at("mean_spp").get<double>();
    p.rays_per_sample = r.meta.at("rays_per_sample").get<double>();
    const image::ImageError e = image::imageError(w, h, r.pixels, reference, tone);
    p.rmse = e.rmse, p.relmse = e.relmse, p.worst_tile_rmse = e.worst_tile_rmse,
    p.worst_tile_relmse = e.worst_tile_relmse;
    std::string file =
        shot.variant.name + "_" +
        (shot.variant.adaptive ? std::string("t") + io::formatNumber(shot.threshold, 3) : std::to_string(shot.spp)) +
        ".png";
    std::replace(file.begin(), file.end(), '+', '-');
    image::writePng(out / "images" / file, image::develop(w, h, r.pixels, tone));
    result.points.push_back(p);
  }
  progress.finish();
  result.fits = fitRenderStudy(result.points, result.reference_rmse);
  return result;
}

}  // namespace wobble
