// render(): tiles in parallel with TBB, per-pixel seeded samples, FTZ/DAZ in render threads (see renderer.h).
#include "renderer.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <xmmintrin.h>
#include <pmmintrin.h>

#include "integrator.h"
#include "scene.h"

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

}  // namespace

Film render(const Scene& scene, const Camera& camera, const RenderSettings& settings, RenderStats* stats) {
  if (!scene.committed()) throw std::logic_error("render: the scene changed since its last commit(); call commit()");
  if (settings.samples_per_pixel < 1 || settings.max_bounces < 0 || settings.tile_size < 1)
    throw std::invalid_argument("render: need samples_per_pixel >= 1, max_bounces >= 0, tile_size >= 1");
  checkLights(scene.lights);  // lights are a plain member: they may have changed since commit()
  const int w = camera.width(), h = camera.height(), ts = settings.tile_size;
  const int tiles_x = (w + ts - 1) / ts, tiles_y = (h + ts - 1) / ts;
  Film film(w, h);
  std::vector<std::uint64_t> tile_rays(std::size_t(tiles_x) * tiles_y, 0);
  const float inv_spp = 1.0f / static_cast<float>(settings.samples_per_pixel);

  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& range) {
    const DenormalsAreZero fp_mode;
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      const int x0 = (tile % tiles_x) * ts, y0 = (tile / tiles_x) * ts;
      std::uint64_t rays = 0;
      for (int y = y0; y < std::min(y0 + ts, h); ++y)
        for (int x = x0; x < std::min(x0 + ts, w); ++x) {
          const std::size_t i = film.index(x, y);
          Rng rng(i, settings.frame);
          Color color = Color::Zero(), albedo = Color::Zero();
          Eigen::Vector3f normal = Eigen::Vector3f::Zero();
          float depth = film.depth[i];
          for (int s = 0; s < settings.samples_per_pixel; ++s) {
            const float jx = rng.next(), jy = rng.next();
            const Ray ray = camera.ray(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
            const PathResult r = tracePath(scene, ray, rng, settings.max_bounces);
            if (r.radiance.allFinite()) color += r.radiance;  // one bad sample must not blacken the pixel
            albedo += r.albedo;
            normal += r.normal;
            if (r.hit) depth = std::min(depth, camera.depth(r.position));
            rays += r.rays;
          }
          film.color[i] = color * inv_spp;
          film.albedo[i] = albedo * inv_spp;
          film.normal[i] = normal * inv_spp;
          film.depth[i] = depth;
        }
      tile_rays[tile] = rays;
    }
  });

  if (stats) {
    stats->camera_rays = std::uint64_t(w) * h * settings.samples_per_pixel;
    stats->rays = 0;
    for (std::uint64_t r : tile_rays) stats->rays += r;
  }
  return film;
}

}  // namespace wobble::render
