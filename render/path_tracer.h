// tracePath: the light arriving along one camera ray, by a short path tracer.
//
// At every surface the path meets it samples each sun and area light (one shadow ray each) and, when the path goes
// on, the sky (if PathSettings::sample_sky); with a caustic photon map (PathContext::caustics) it adds the suns'
// light through gelatine from the map instead of finding it by chance; then it continues in a direction drawn from
// the BSDF. A continuation
// that escapes picks up the sky and any sun disc it points into; one that passes an area light picks that up. Light
// and BSDF samples of the same light are weighted by the power heuristic (Veach 1995), so each light is counted once
// and noise goes to whichever strategy does better. At the last vertex (no continuation) light samples count fully.
// With Russian roulette (PathSettings::roulette) continuations after the first are taken with the path's throughput
// as probability.
// max_bounces counts the continuations: 0 = direct light only (no sky on surfaces), 1 = one indirect bounce (sky
// light and colour bleeding onto surfaces: the "ambient" term), 2 = two bounces (the default; light between the jelly
// and the floor). Camera rays see the sky only (suns and area lights are not drawn). "The sky" is the scene's
// Background (lights.h): its environment map when it has one, else the elevation gradient.
//
// Every random number comes from the pixel's sampler at a fixed slot (sampler.h: pixel jitter, texture filter, then
// per bounce one 2D slot per light, the sky, the lobe, the direction and Russian roulette), so the path is a pure
// function of (pixel, frame, sample).
//
// For the denoiser the result is split at the first surface: `diffuse` is the light its diffuse lobe reflects
// (a multiple of its base colour, which the denoiser divides out), the rest of `radiance` comes from the coat,
// and the sky seen directly.
#pragma once
#include <cstdint>
#include <vector>

#include "render/color.h"
#include "render/lights.h"
#include "render/ray.h"
#include "render/sampler.h"

namespace wobble::render {

class Camera;
class CausticMap;
class CausticMaps;
class Scene;

// Gelatine: the most interfaces (reflections and refractions, as Cycles' 12 transmission bounces) a path or a caustic
// photon crosses; they do not count against max_bounces.
constexpr int kMaxInterfaceEvents = 64;

struct PathSettings {
  int max_bounces = 2;
  bool sample_sky = false;  // next-event estimation of the sky, with MIS against BSDF sampling
  // false: suns and area lights by light sampling alone (full weight; BSDF samples that find them are ignored), as
  // the renderer did before MIS. For the render study's comparison.
  bool mis = true;
  // false: suns and area lights by BSDF sampling alone (no light samples; a continuation that finds one counts it
  // fully), the other strategy MIS combines. For tests of MIS's variance: light at the last vertex is lost.
  bool light_samples = true;
  // Russian roulette from the second continuation on: a path goes on with its throughput as probability (at least
  // 0.05) and is weighted by its inverse (unbiased), so dim indirect light costs fewer rays.
  bool roulette = false;
  // Cycles' clamp_indirect: light found after the path's first scattering vertex (counting every surface and
  // interface the path scattered at, as Cycles counts bounces) adds at most this much to a sample, as the mean of its
  // R, G and B (scaled down, hue kept); 0: no clamp. Biased (it removes energy) but cuts the rare bright samples
  // (fireflies) of caustic paths such as sunlight through gelatine found by a floor's BSDF sample.
  float clamp_indirect = 0;
};

// What the first hit's texture filter needs of the camera ray. The first surface's texture is averaged over the
// whole pixel's footprint (the neighbouring pixels' rays met on the hit's tangent plane), centred on the pixel's
// centre rather than on the sample: every sample of a pixel then sees the same box-filtered texture, so texture
// detail adds no noise at any sample count, and its mean is the pixel's box filter, as the reference's.
// The ray differentials are asked of the camera only when the first hit is textured (sky and plain surfaces skip them).
struct CameraSample {
  const Camera* camera = nullptr;  // its ray differentials (camera.h); none: the texture is point-sampled
  Eigen::Vector2f offset = Eigen::Vector2f::Zero();  // the sample's position in its pixel minus the centre (pixels)
  // At a gelatine surface met by the camera ray: which branch to follow instead of drawing one (tracePath below).
  enum class Branch { Drawn, Interface, Reflect, Print } branch = Branch::Drawn;
};

// What a path needs besides its ray, built once per frame (render()).
struct PathContext {
  PathContext(const Scene& scene, const PathSettings& settings, const CausticMaps* caustics = nullptr);

  const Scene& scene;
  PathSettings settings;
  SampleLayout layout;
  Background background;  // the sky or the environment map (lights.h)
  std::vector<SunCone> suns;
  // The frame's caustic photon maps (caustic_photons.h), or none: at every surface that is not gelatine the path adds
  // its sample's map's density estimate, and drops the suns its continuations find through smooth gelatine alone.
  const CausticMaps* caustics = nullptr;
};

struct PathResult {
  Color radiance = Color::Zero();
  Color diffuse = Color::Zero();  // the part reflected by the first surface's diffuse lobe
  float diffuse_demodulated = 0;  // luminance of diffuse / base colour (for the denoiser's variance)
  // First-hit values for the EXR layers; albedo and normal stay zero and t infinite when the ray escapes.
  Color albedo = Color::Zero();
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // shading normal, turned towards the camera
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  // How the first hit's point (the guides' position) moves over the whole shutter, per unit of ray time (its
  // SurfaceHit::dpdt: zero for a still shape), for the film's motion layer.
  Eigen::Vector3f velocity = Eigen::Vector3f::Zero();
  bool hit = false;
  std::uint32_t rays = 0;  // rays traced (intersection and shadow), for statistics
  // The camera ray met gelatine first: its print coverage and (smooth interface) Fresnel reflectance there.
  bool gelatine_first = false;
  float print = 0, reflectance = 0;
  // The gelatine surface met first: its normal (turned towards the camera) and point; tracePathSplit makes them the
  // guides.
  Eigen::Vector3f front_normal = Eigen::Vector3f::Zero(), front_position = Eigen::Vector3f::Zero();
  // tracePathSplit: the light seen through that surface (the refraction branch's share of radiance), whose own error
  // adaptive sampling weighs (renderer.h).
  Color through = Color::Zero();
};

PathResult tracePath(const PathContext& context, Ray ray, const CameraSample& camera, const PixelSampler& sampler,
                     std::uint32_t sample);

// tracePath, but where the camera ray meets gelatine first every branch there is followed, weighted by its
// probability: the print (coverage c), the reflection (1 - c) F and the refraction (1 - c)(1 - F) of a smooth surface
// (a rough one: the interface, (1 - c), its lobe drawn). The expectation is tracePath's, without the noise of that
// first choice, which at one sample per pixel would speckle the jelly beyond what the denoiser can smooth (its guides
// would jump between the print, the mirror image and what is seen through). The guides' normal and position are then
// the gelatine's surface (front_normal, front_position), its albedo the branches' albedos weighted alike. Elsewhere it
// is tracePath.
PathResult tracePathSplit(const PathContext& context, const Ray& ray, CameraSample camera, const PixelSampler& sampler,
                          std::uint32_t sample);

// Origin for rays leaving a surface at p on the side of the unit normal n: far enough to not hit the same surface
// again through rounding (relative to the coordinates' magnitude), close enough to keep contact shadows.
Eigen::Vector3f offsetFromSurface(const Eigen::Vector3f& p, const Eigen::Vector3f& n);

// Whether nothing in the scene blocks the shadow ray of a light sample (LightSample::shadow) between its tnear and
// tfar: the one visibility test of the path tracer (pbrt's Unoccluded). Lights only say where to look. `leaving`: the
// shape the ray starts on (Scene::occluded), or -1.
bool unoccluded(const Scene& scene, const Ray& shadow, int leaving = -1);

}  // namespace wobble::render
