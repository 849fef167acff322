// render: draws a committed Scene through a Camera into a Film.
//
// Parameters (RenderSettings):
//   samples_per_pixel  the most samples a pixel gets, averaged (box filter): the anti-aliasing (>= 1)
//   min_samples        adaptive sampling (with noise_threshold > 0): every pixel first gets min_samples, then
//                      pixels whose estimated error is still above the threshold double their count, pass after
//                      pass, up to samples_per_pixel. 0 picks min(samples_per_pixel, 4).
//   noise_threshold    0 = no adaptive sampling. Otherwise a pixel stops once Cycles' error estimate (Hachisuka et
//                      al.'s, as in Cycles' adaptive sampling) falls below it: the RGB difference between the mean
//                      of all its samples and of the first half, over the square root of the mean's RGB sum. A pixel
//                      with a single sample (min_samples 1) estimates that from its 3 x 3 neighbourhood's spread of
//                      received light (colour with the diffuse part divided by the albedo, so texture is not noise),
//                      so easy pixels can stop at one sample. A pixel next to one that goes on goes on too (a 3 x 3
//                      dilation, as Cycles), so isolated pixels that stopped by luck do not show. A pixel whose
//                      camera ray meets gelatine first takes a second sample in any case (the neighbourhood's spread
//                      there is the refracted detail), and from two on the error of the light seen through it
//                      (PathResult::through) counts too, against that light's own brightness.
//   max_bounces        path continuations after the first hit (path_tracer.h); 2 by default
//   sampler            SamplerKind::Sobol (default) or Independent (sampler.h)
//   sample_sky         next-event estimation of the sky with MIS (path_tracer.h)
//   mis                multiple importance sampling of suns and area lights (path_tracer.h); off only for comparisons
//   light_samples      false: suns and area lights by BSDF sampling alone (path_tracer.h); for tests of MIS only
//   roulette           Russian roulette from the second path continuation on, by throughput (path_tracer.h)
//   clamp_indirect     the most indirect light one sample may add, 0 = no clamp (PathSettings, path_tracer.h)
//   caustics           the caustic photon map's photons per sun and kernel radius (caustic_photons.h), shot once
//                      per frame before the pixels; 0 photons: no map (the path tracer finds caustics by chance)
//   tile_size          tiles of tile_size^2 pixels are the units of parallel work (tbb::parallel_for)
//   motion_blur        trace each sample at its own instant of the shutter (Ray::time, drawn from the sampler's kTime
//                      slot, sampler.h), so shapes with several poses and a moving camera blur (scene.h, camera.h);
//                      false: every ray at time 0, and the same bytes as a renderer without motion blur. With it,
//                      the film's motion layer records how far each first hit moves on the image (Camera::screenMotion)
//   frame              animation frame index: seeds the per-pixel sample streams, so consecutive frames get
//                      different noise and the same frame is always the same
// Determinism: every pixel's samples are a function of (pixel, frame, sample index) only, each pixel is computed by
// one thread in a fixed order, adaptive decisions use only finished passes, and nothing is summed across threads
// except integer statistics, so the image's bytes do not depend on the thread count or scheduling. Render threads
// run with flush-to-zero and denormals-are-zero (as Embree recommends for speed); the caller's floating-point mode is
// restored afterwards.
#pragma once
#include <cstdint>

#include "image/film.h"
#include "render/camera.h"
#include "render/caustic_photons.h"
#include "render/sampler.h"

namespace wobble::render {

class Scene;

struct RenderSettings {
  int samples_per_pixel = 16;
  int min_samples = 0;
  float noise_threshold = 0;
  int max_bounces = 2;
  SamplerKind sampler = SamplerKind::Sobol;
  bool sample_sky = false;
  bool mis = true;
  bool light_samples = true;
  bool roulette = false;
  float clamp_indirect = 0;
  CausticSettings caustics;  // photons 0: none
  int tile_size = 16;
  bool motion_blur = false;
  std::uint32_t frame = 0;
};

struct RenderStats {
  std::uint64_t camera_rays = 0;  // = samples taken, over all pixels
  std::uint64_t rays = 0;         // every ray traced: camera, bounce and shadow rays
  int passes = 0;                 // adaptive passes (1 without adaptive sampling)
};

// Throws std::logic_error if the scene has changes that were not committed, std::invalid_argument on bad settings.
image::Film render(const Scene& scene, const Camera& camera, const RenderSettings& settings = {},
                   RenderStats* stats = nullptr);

}  // namespace wobble::render
