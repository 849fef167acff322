#include "app/study/study_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "app/output/progress.h"
#include "app/scene/input_error.h"
#include "app/scene/render_overrides.h"
#include "app/scene/scene_file.h"
#include "app/study/order_fit.h"
#include "app/study/study_report.h"
#include "app/view/frame_view.h"
#include "app/view/render_scene.h"
#include "io/content_hash.h"
#include "io/text_file.h"
#include "io/text_table.h"
#include "render/denoiser.h"
#include "render/image/image_error.h"
#include "render/image/pfm_io.h"
#include "render/image/png_io.h"
#include "render/renderer.h"
#include "render/scene_export.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Bumped whenever the renderer's converged picture changes, so cached references of older builds are not reused.
constexpr int kRendererVersion = 5;
// The second half of the reference uses this seed offset: far from any frame number.
constexpr std::uint32_t kSecondHalfSeed = 0x80000000u;

render::RenderSettings settingsFor(const RenderVariant& v, int spp, double threshold, int bounces, int frame) {
  render::RenderSettings s;
  s.samples_per_pixel = spp;
  s.max_bounces = v.bounces >= 0 ? v.bounces : bounces;
  render::parseSamplerKind(v.sampler, s.sampler);
  s.sample_sky = v.sky_sampling;
  s.mis = v.mis;
  s.roulette = v.roulette;
  s.noise_threshold = v.adaptive ? static_cast<float>(threshold) : 0.0f;
  s.min_samples = v.adaptive ? 1 : 0;
  s.frame = static_cast<std::uint32_t>(frame);
  return s;
}

std::string pointLabel(const RenderPoint& p) {
  return p.threshold > 0 ? "threshold " + io::formatNumber(p.threshold, 3) : std::to_string(p.spp) + " spp";
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
  std::vector<std::string> overrides = o.sets;
  for (const std::string& s : renderOverrides(flags)) overrides.push_back(s);
  const SceneFile scene = loadScene(o.scene, overrides);
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
  render::ToneMap tone;
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
  const std::string hex = io::hashOf(key.str());  // stable across builds, unlike std::hash
  result.reference_file = out / ("reference-" + hex + ".pfm");
  const fs::path second_half = out / ("reference-" + hex + "-b.pfm");
  std::vector<render::Color> reference, half_b;
  if (fs::exists(result.reference_file) && fs::exists(second_half)) {
    render::FloatImage a = render::readPfm(result.reference_file), b = render::readPfm(second_half);
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
    render::Film a =
        render::render(view.scene.scene(), camera, settingsFor(sobol, o.reference_spp / 2, 0, result.bounces, frame));
    tick();
    render::Film b =
        render::render(view.scene.scene(), camera,
                       settingsFor(sobol, o.reference_spp / 2, 0, result.bounces, frame ^ kSecondHalfSeed));
    tick();
    result.reference_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    reference = std::move(a.color);
    half_b = std::move(b.color);
    // Stored as its two halves: the first file holds half a, completed below to the mean before use.
    render::writePfm(second_half, w, h, half_b);
    render::writePfm(result.reference_file, w, h, reference);
  }
  const render::ImageError halves = render::imageError(w, h, reference, half_b, tone);
  for (std::size_t i = 0; i < reference.size(); ++i) reference[i] = 0.5f * (reference[i] + half_b[i]);
  result.reference_rmse = halves.rmse / 2;
  render::writePng(out / "reference.png", render::develop(w, h, reference, tone));

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
      std::vector<render::Color> image;
      render::RenderStats stats;
      for (int r = 0; r < o.repeats; ++r) {
        const auto start = Clock::now();
        render::Film film =
            render::render(view.scene.scene(), camera, settingsFor(v, spp, threshold, result.bounces, frame), &stats);
        const auto rendered = Clock::now();
        image = v.denoise ? render::denoise(film) : std::move(film.color);
        const auto end = Clock::now();
        p.seconds = std::min(p.seconds, std::chrono::duration<double>(end - start).count());
        p.denoise_seconds = std::min(p.denoise_seconds, std::chrono::duration<double>(end - rendered).count());
      }
      if (!v.denoise) p.denoise_seconds = 0;
      p.mean_spp = double(stats.camera_rays) / double(std::size_t(w) * h);
      p.rays_per_sample = double(stats.rays) / double(stats.camera_rays);
      const render::ImageError e = render::imageError(w, h, image, reference, tone);
      p.rmse = e.rmse, p.relmse = e.relmse, p.worst_tile_rmse = e.worst_tile_rmse,
      p.worst_tile_relmse = e.worst_tile_relmse;
      std::string file = v.name + "_" +
                         (v.adaptive ? std::string("t") + io::formatNumber(threshold, 3) : std::to_string(spp)) +
                         ".png";
      std::replace(file.begin(), file.end(), '+', '-');
      render::writePng(out / "images" / file, render::develop(w, h, image, tone));
      result.points.push_back(p);
      tick();
    }
  }
  progress.finish();
  result.fits = fitRenderStudy(result.points, result.reference_rmse);
  return result;
}

std::string renderStudyMarkdown(const RenderStudyResult& r) {
  std::ostringstream md;
  md << "# Render study: " << r.scene_name << ", frame " << r.frame << "\n\n";
  md << "Scene `" << r.scene_file.string() << "`, " << r.width << " x " << r.height << ", " << r.bounces
     << " bounces. Machine: " << machineDescription() << ".\n\n";
  md << "- Reference: " << r.reference_spp << " spp (Sobol, two halves with independent seeds), "
     << (r.reference_cached ? "read from the cache" : "rendered in " + io::formatNumber(r.reference_seconds, 3) + " s")
     << "; its own RMSE is about " << io::formatNumber(r.reference_rmse, 3)
     << " (half the RMSE between its halves): errors below twice that are left out of the slopes.\n"
     << "- RMSE: of display values (tone-mapped, sRGB-encoded, 0..1, as in the PNG) over all pixels and channels; "
        "relMSE: (x - ref)^2 / (ref^2 + 0.01) of linear colour. Worst tile: the 32 x 32 tile with the largest error.\n"
     << "- Time: wall time of rendering plus denoising on all cores (minimum over the repeats).\n\n";

  md << "## Convergence: slope of log RMSE against log samples per pixel\n\n"
        "Plain Monte Carlo converges as spp^-0.5; a steeper (more negative) slope means error falls faster than "
        "1/sqrt(spp). Denoised variants are flat by design: most of their error is the filter's bias.\n\n";
  io::TextTable slopes{{"variant", "slope", "points in fit"}};
  for (const RenderVariantFit& f : r.fits)
    slopes.add({f.variant, std::isnan(f.slope) ? "n/a" : io::formatNumber(f.slope, 3), std::to_string(f.points)});
  md << slopes.markdown() << "\n";

  md << "## Samples per pixel and time to reach an error\n\n"
        "Interpolated (log-log) between the two sweep points around each target RMSE; \"-\" where the sweep never "
        "reached it.\n\n";
  const std::vector<double> targets = {0.05, 0.02, 0.01, 0.005, 0.002, 0.001};
  std::vector<std::string> header = {"variant"};
  for (double t : targets) header.push_back("RMSE " + io::formatNumber(t) + ": spp / s");
  io::TextTable reach{header};
  std::vector<std::string> names;
  for (const RenderPoint& p : r.points)
    if (std::find(names.begin(), names.end(), p.variant) == names.end()) names.push_back(p.variant);
  for (const std::string& name : names) {
    std::vector<const RenderPoint*> curve;
    for (const RenderPoint& p : r.points)
      if (p.variant == name) curve.push_back(&p);
    std::sort(curve.begin(), curve.end(), [](auto* a, auto* b) { return a->mean_spp < b->mean_spp; });
    std::vector<std::string> row = {name};
    for (double target : targets) {
      std::string cell = "-";
      for (std::size_t i = 0; i < curve.size(); ++i) {
        if (curve[i]->rmse > target) continue;
        if (i == 0) {
          cell = "<= " + io::formatNumber(curve[0]->mean_spp, 3) + " / " + io::formatNumber(curve[0]->seconds, 3);
        } else {
          const RenderPoint &a = *curve[i - 1], &b = *curve[i];
          const double f = std::log(target / a.rmse) / std::log(b.rmse / a.rmse);
          const auto lerp = [&](double x, double y) { return std::exp(std::log(x) + f * (std::log(y) - std::log(x))); };
          cell = io::formatNumber(lerp(a.mean_spp, b.mean_spp), 3) + " / " +
                 io::formatNumber(lerp(a.seconds, b.seconds), 3);
        }
        break;
      }
      row.push_back(cell);
    }
    reach.add(row);
  }
  md << reach.markdown() << "\n";

  md << "## Every point\n\n";
  io::TextTable all{{"variant", "setting", "mean spp", "RMSE", "worst tile RMSE", "relMSE", "worst tile relMSE",
                     "time (s)", "of which denoising (s)"}};
  for (const RenderPoint& p : r.points)
    all.add({p.variant, pointLabel(p), io::formatNumber(p.mean_spp, 4), io::formatNumber(p.rmse, 3),
             io::formatNumber(p.worst_tile_rmse, 3), io::formatNumber(p.relmse, 3),
             io::formatNumber(p.worst_tile_relmse, 3), io::formatNumber(p.seconds, 3),
             io::formatNumber(p.denoise_seconds, 3)});
  md << all.markdown() << "\n";
  md << "## Variants\n\n";
  for (const RenderVariant& v : renderStudyVariants())
    if (std::find(names.begin(), names.end(), v.name) != names.end())
      md << "- `" << v.name << "`: " << v.description << "\n";
  return md.str();
}

PlotResult writeRenderStudyOutputs(const RenderStudyResult& r, const fs::path& out, const std::string& gnuplot) {
  fs::create_directories(out);
  io::TextTable csv{{"scene", "frame", "width", "height", "variant", "spp", "threshold", "mean_spp", "rmse", "relmse",
                     "worst_tile_rmse", "worst_tile_relmse", "seconds", "denoise_seconds", "rays_per_sample",
                     "reference_rmse"}};
  for (const RenderPoint& p : r.points)
    csv.add({r.scene_name, std::to_string(r.frame), std::to_string(r.width), std::to_string(r.height), p.variant,
             std::to_string(p.spp), io::formatNumber(p.threshold, 4), io::formatNumber(p.mean_spp, 6),
             io::formatNumber(p.rmse, 6), io::formatNumber(p.relmse, 6), io::formatNumber(p.worst_tile_rmse, 6),
             io::formatNumber(p.worst_tile_relmse, 6), io::formatNumber(p.seconds, 6),
             io::formatNumber(p.denoise_seconds, 6), io::formatNumber(p.rays_per_sample, 4),
             io::formatNumber(r.reference_rmse, 6)});
  io::writeTextFile(out / "render.csv", csv.csv());
  io::writeTextFile(out / "render.md", renderStudyMarkdown(r));

  std::ostringstream gp;
  gp << "# Work-precision diagram of the renderer on " << r.scene_name << ": gnuplot render.gp (writes render.png)\n"
     << "if (!exists(\"out\")) out = 'render.png'\n"
     << "set terminal pngcairo size 1400,600 noenhanced\nset output out\n"
     << "set logscale xy\nset grid\nset key top right\nset format x '%g'\n";
  std::vector<std::string> names;
  for (const RenderPoint& p : r.points)
    if (std::find(names.begin(), names.end(), p.variant) == names.end()) names.push_back(p.variant);
  for (std::size_t i = 0; i < names.size(); ++i) {
    gp << "$d" << i << " << EOD\n";
    for (const RenderPoint& p : r.points)
      if (p.variant == names[i])
        gp << io::formatNumber(p.rmse, 8) << " " << io::formatNumber(p.seconds, 6) << " "
           << io::formatNumber(p.mean_spp, 6) << "\n";
    gp << "EOD\n";
  }
  gp << "set multiplot layout 1,2 title "
     << gnuplotQuote("wobble study render: " + r.scene_name + " frame " + std::to_string(r.frame) + ", " +
                     std::to_string(r.width) + "x" + std::to_string(r.height))
     << "\n";
  for (int panel = 0; panel < 2; ++panel) {
    gp << (panel == 0 ? "set xlabel 'RMSE (display values)'\nset ylabel 'render time (s)'\n"
                      : "set xlabel 'samples per pixel (mean)'\nset ylabel 'RMSE (display values)'\n")
       << "plot ";
    for (std::size_t i = 0; i < names.size(); ++i)
      gp << (i ? ", " : "") << "$d" << i << " using " << (panel == 0 ? "1:2" : "3:1")
         << " with linespoints lw 2 pt 7 title " << gnuplotQuote(names[i]);
    if (panel == 1)
      gp << ", " << io::formatNumber(r.points.empty() ? 0.1 : r.points.front().rmse, 6)
         << " / sqrt(x) dt 2 lc 'grey' title '1/sqrt(spp)'";
    gp << "\n";
  }
  gp << "unset multiplot\n";
  io::writeTextFile(out / "render.gp", gp.str());
  return runGnuplot(out / "render.gp", out / "render.png", gnuplot);
}

}  // namespace wobble
