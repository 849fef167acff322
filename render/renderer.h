// render: draws a committed Scene through a Camera into a Film.
//
// Parameters (RenderSettings):
//   samples_per_pixel  jittered samples in each pixel, averaged (box filter): the anti-aliasing (>= 1)
//   max_bounces        path continuations after the first hit (integrator.h); 2 by default
//   tile_size          tiles of tile_size^2 pixels are the units of parallel work (tbb::parallel_for)
//   frame              animation frame index: seeds the per-pixel random numbers, so consecutive frames get
//                      different noise and the same frame is always the same
// Determinism: every pixel's random numbers come from its own generator seeded by (pixel index, frame), each pixel
// is computed by one thread in a fixed order, and nothing is summed across threads except integer statistics, so
// the image's bytes do not depend on the thread count or scheduling. Render threads run with flush-to-zero and
// denormals-are-zero (as Embree recommends for speed); the caller's floating-point mode is restored afterwards.
#pragma once
#include <cstdint>

#include "camera.h"
#include "film.h"

namespace wobble::render {

class Scene;

struct RenderSettings {
  int samples_per_pixel = 16;
  int max_bounces = 2;
  int tile_size = 16;
  std::uint32_t frame = 0;
};

struct RenderStats {
  std::uint64_t camera_rays = 0;
  std::uint64_t rays = 0;  // every ray traced: camera, bounce and shadow rays
};

// Throws std::logic_error if the scene has changes that were not committed, std::invalid_argument on bad settings.
Film render(const Scene& scene, const Camera& camera, const RenderSettings& settings = {},
            RenderStats* stats = nullptr);

}  // namespace wobble::render
