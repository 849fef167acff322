// render(): tiles in parallel with TBB, adaptive passes, per-pixel sample streams, FTZ/DAZ in render threads
// (see renderer.h).
#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <pmmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <xmmintrin.h>

#include "render/path_tracer.h"
#include "render/scene.h"

namespace wobble::render {

namespace {

// Sets FTZ/DAZ for the current thread and restores the previous mode on exit: TBB may run a tile on the calling
// thread, whose floating-point mode must not leak out of render().
class DenormalsAreZero {
 public:
  DenormalsAreZero() : saved_(_mm_getcsr()) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  }
  ~DenormalsAreZero() { _mm_setcsr(saved_); }
  DenormalsAreZero(const DenormalsAreZero&) = delete;
  DenormalsAreZero& operator=(const DenormalsAreZero&) = delete;

 private:
  unsigned saved_;
};

// What a pixel keeps between passes besides the film's running sums.
struct PixelState {
  Color half = Color::Zero();  // colour sum over the first half of the samples taken by the end of the pass
  float diffuse_sum = 0, diffuse_sq = 0, other_sum = 0, other_sq = 0;  // luminance moments, for the variances
  // The light seen through gelatine met first (PathResult::through): its sums over all samples and the first half.
  Color through_sum = Color::Zero(), through_half = Color::Zero();
  bool active = true;
  bool gelatine = false;  // a camera ray met gelatine first
};

// Variance of the mean of n samples with sum s and sum of squares q; -1 when n < 2.
float varianceOfMean(float s, float q, std::uint32_t n) {
  if (n < 2) return -1;
  const float m = s / float(n);
  return std::max(0.0f, (q / float(n) - m * m) / float(n - 1));
}

// Cycles' per-pixel error estimate (adaptive_sampling.h there): |I - A|_1 / sqrt(sum I), I the mean of all n
// samples, A that of the first n/2.
float adaptiveError(const Color& sum, const Color& half, std::uint32_t n) {
  const Color all = sum / float(n), first = half / float(n / 2);
  return (all - first).cwiseAbs().sum() / (1e-4f + std::sqrt(std::max(0.0f, all.sum())));
}

// The light a pixel receives, per sample: its colour with the diffuse part divided by the albedo, so that texture
// detail does not count as noise.
Color receivedLight(const image::Film& film, std::size_t i) {
  const Color light = film.diffuse[i].cwiseQuotient(film.albedo[i].cwiseMax(0.05f * film.samples[i])) +
                      (film.color[i] - film.diffuse[i]) / float(film.samples[i]);
  return light;
}

// One sample has no spread of its own: estimate it from the 3 x 3 neighbourhood's spread of received light. The
// spread over sqrt(2) stands for the difference of two samples' mean and one sample's, in the same measure as
// adaptiveError. Lighting that varies across the neighbourhood (a shadow's edge) counts too, so the estimate errs
// towards more samples.
float neighbourhoodError(const std::vector<Color>& light, int w, int h, int x, int y) {
  Color sum = Color::Zero(), sq = Color::Zero();
  int n = 0;
  for (int ny = std::max(0, y - 1); ny <= std::min(h - 1, y + 1); ++ny)
    for (int nx = std::max(0, x - 1); nx <= std::min(w - 1, x + 1); ++nx) {
      const Color& c = light[std::size_t(ny) * w + nx];
      sum += c, sq += c.cwiseProduct(c), ++n;
    }
  const Color mean = sum / float(n);
  const Color spread = (sq / float(n) - mean.cwiseProduct(mean)).cwiseMax(0.0f).cwiseSqrt();
  const Color& own = light[std::size_t(y) * w + x];
  return spread.sum() / std::sqrt(2.0f) / (1e-4f + std::sqrt(std::max(0.0f, own.sum())));
}

}  // namespace

image::Film render(const Scene& scene, const Camera& camera, const RenderSettings& settings, RenderStats* stats) {
  if (!scene.committed()) throw std::logic_error("render: the scene changed since its last commit(); call commit()");
  if (settings.samples_per_pixel < 1 || settings.max_bounces < 0 || settings.tile_size < 1 ||
      settings.min_samples < 0 || !(settings.noise_threshold >= 0) || settings.caustics.photons < 0 ||
      !(settings.caustics.radius > 0 && std::isfinite(settings.caustics.radius)))
    throw std::invalid_argument(
        "render: need samples_per_pixel >= 1, min_samples >= 0, noise_threshold >= 0, "
        "max_bounces >= 0, tile_size >= 1, caustic photons >= 0 and a caustic radius > 0");
  checkLights(scene.lights);  // lights are a plain member: they may have changed since commit()
  const int spp = settings.samples_per_pixel;
  const bool adaptive = settings.noise_threshold > 0;
  int target = adaptive ? std::min(spp, settings.min_samples > 0 ? settings.min_samples : 4) : spp;
  const bool caustics = settings.caustics.photons > 0;
  CausticMaps caustic_maps(scene, settings.caustics, settings.frame, settings.motion_blur);
  const PathContext context(scene,
                            PathSettings{settings.max_bounces, settings.sample_sky, settings.mis,
                                         settings.light_samples, settings.roulette, settings.clamp_indirect},
                            caustics ? &caustic_maps : nullptr);
  const int w = camera.width(), h = camera.height(), ts = settings.tile_size;
  const bool lens = camera.hasLens();
  const int tiles_x = (w + ts - 1) / ts, tiles_y = (h + ts - 1) / ts;
  // One sample per pixel (the default): a single pass, no moments to keep (a variance needs two samples: -1) and
  // nothing to normalise. The film is then set pixel by pixel as it is rendered, with no per-pixel state and no
  // final pass: about 150 MB less memory traffic a 720p frame.
  const bool single = spp == 1;
  image::Film film = single ? image::Film::unfilled(w, h) : image::Film(w, h);
  std::vector<PixelState> state(single ? 0 : film.color.size());
  std::vector<std::uint64_t> tile_rays(std::size_t(tiles_x) * tiles_y, 0);

  // A pixel's only sample is a uniform random point in every slot, whichever the pattern: hashing it directly
  // (Independent) gives the same distribution for half the work of the shuffled, scrambled Sobol point.
  const SamplerKind sampler_kind = spp == 1 ? SamplerKind::Independent : settings.sampler;
  int passes = 0;
  for (;;) {
    ++passes;
    if (caustics) caustic_maps.cover(target);  // the maps this pass's samples read (caustic_photons.h)
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& range) {
      const DenormalsAreZero fp_mode;
      for (int tile = range.begin(); tile != range.end(); ++tile) {
        const int x0 = (tile % tiles_x) * ts, y0 = (tile / tiles_x) * ts;
        std::uint64_t rays = 0;
        for (int y = y0; y < std::min(y0 + ts, h); ++y)
          for (int x = x0; x < std::min(x0 + ts, w); ++x) {
            const std::size_t i = film.index(x, y);
            PixelState* p = single ? nullptr : &state[i];
            if (p && !p->active) continue;
            if (single) film.clearPixel(i);  // an unfilled film: set as Film(w, h) starts
            const PixelSampler sampler(sampler_kind, i, settings.frame);
            for (auto s = film.samples[i]; s < std::uint32_t(target); ++s) {
              if (p && s == std::uint32_t(target / 2)) p->half = film.color[i], p->through_half = p->through_sum;
              const Eigen::Vector2f jitter = sampler.get2D(s, SampleLayout::kPixel);
              const float fx = static_cast<float>(x) + jitter.x(), fy = static_cast<float>(y) + jitter.y();
              Ray ray =
                  camera.hasLens() ? camera.ray(fx, fy, sampler.get2D(s, SampleLayout::kLens)) : camera.ray(fx, fy);
              if (settings.motion_blur) ray = camera.atTime(ray, sampler.get1D(s, SampleLayout::kTime));
              CameraSample cs;
              cs.camera = &camera;
              cs.offset = jitter.array() - 0.5f;
              const PathResult r = tracePathSplit(context, ray, cs, sampler, s);
              if (p && r.gelatine_first) p->gelatine = true, p->through_sum += r.through;
              if (r.radiance.allFinite()) {  // one bad sample must not blacken the pixel
                film.color[i] += r.radiance;
                film.diffuse[i] += r.diffuse;
                if (p) {
                  const float d = r.diffuse_demodulated, o = luminance(r.radiance - r.diffuse);
                  p->diffuse_sum += d, p->diffuse_sq += d * d, p->other_sum += o, p->other_sq += o * o;
                }
              }
              film.albedo[i] += r.albedo;
              film.normal[i] += r.normal;
              const float depth = r.hit ? camera.depth(r.position) : std::numeric_limits<float>::infinity();
              film.depth[i] = std::min(film.depth[i], depth);
              if (lens) film.blur[i] += camera.blurRadius(depth);
              if (settings.motion_blur && r.hit)
                film.motion[i] += camera.screenMotion(r.position, r.velocity, ray.time);
              rays += r.rays;
            }
            film.samples[i] = std::uint32_t(target);
          }
        tile_rays[tile] += rays;
      }
    });
    if (!adaptive || target >= spp) break;

    // Which pixels go on: those not converged and their 3 x 3 neighbours.
    const auto rows = [&](const auto& body) {
      tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y) body(y);
      });
    };
    // Only pixels sampled in this pass can change their mind; the first pass samples every pixel, each with one
    // sample when min_samples is 1, and needs the neighbourhood estimate (received light per pixel) once.
    std::vector<Color> light;
    if (passes == 1 && target < 2) {
      light.resize(state.size());
      rows([&](int y) {
        for (int x = 0; x < w; ++x) light[film.index(x, y)] = receivedLight(film, film.index(x, y));
      });
    }
    std::vector<char> unconverged(state.size(), 0);
    rows([&](int y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = film.index(x, y);
        if (!state[i].active) continue;
        const std::uint32_t n = film.samples[i];
        const float error =
            n < 2 ? neighbourhoodError(light, w, h, x, y) : adaptiveError(film.color[i], state[i].half, n);
        unconverged[i] = error >= settings.noise_threshold;
        // Seen through gelatine: one sample says nothing of the spread of the light behind it (the neighbours'
        // spread is the refracted print's and floor's detail), so such a pixel takes a second; from two on, that
        // light's own error counts too, against its own brightness (the clear interface's reflection and the print
        // would otherwise hide it).
        if (state[i].gelatine)
          unconverged[i] = n < 2 || std::max(error, adaptiveError(state[i].through_sum, state[i].through_half, n)) >=
                                        settings.noise_threshold;
      }
    });
    std::vector<char> row_active(h, 0);
    rows([&](int y) {
      for (int x = 0; x < w; ++x) {
        bool go_on = false;
        for (int ny = std::max(0, y - 1); ny <= std::min(h - 1, y + 1) && !go_on; ++ny)
          for (int nx = std::max(0, x - 1); nx <= std::min(w - 1, x + 1) && !go_on; ++nx)
            go_on = unconverged[film.index(nx, ny)];
        state[film.index(x, y)].active = go_on;
        row_active[y] |= go_on;
      }
    });
    const bool any = std::find(row_active.begin(), row_active.end(), 1) != row_active.end();
    if (!any) break;
    target = std::min(spp, 2 * target);
  }

  if (!single)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, film.color.size()), [&](const auto& pixels) {
      for (std::size_t i = pixels.begin(); i != pixels.end(); ++i) {
        const std::uint32_t n = film.samples[i];
        const float inv = 1.0f / float(n);
        film.color[i] *= inv;
        film.diffuse[i] *= inv;
        film.albedo[i] *= inv;
        film.normal[i] *= inv;
        film.blur[i] *= inv;
        film.motion[i] *= inv;
        film.variance_diffuse[i] = varianceOfMean(state[i].diffuse_sum, state[i].diffuse_sq, n);
        film.variance_other[i] = varianceOfMean(state[i].other_sum, state[i].other_sq, n);
      }
    });
  std::uint64_t samples_taken = 0;
  for (const std::uint32_t n : film.samples) samples_taken += n;
  if (stats) {
    stats->camera_rays = samples_taken;
    stats->passes = passes;
    stats->rays = 0;
    for (std::uint64_t r : tile_rays) stats->rays += r;
  }
  return film;
}

}  // namespace wobble::render
