// tracePath: the light arriving along one camera ray, by a short path tracer.
//
// At every surface the path meets it adds the light of each sun and area light (one shadow ray each), then
// continues in a direction drawn from the BSDF; a path that escapes picks up the sky. max_bounces counts those
// continuations: 0 = direct light only (no sky on surfaces), 1 = one indirect bounce (sky light and colour bleeding
// onto surfaces: the "ambient" term), 2 = two bounces (the default; light between the jelly and the floor).
// Parameters: scene (committed), ray (unit direction), rng (the pixel's generator), max_bounces (>= 0).
#pragma once
#include <cstdint>

#include "color.h"
#include "ray.h"
#include "rng.h"

namespace wobble::render {

class Scene;

struct PathResult {
  Color radiance = Color::Zero();
  // First-hit values for the EXR layers; albedo and normal stay zero and t infinite when the ray escapes.
  Color albedo = Color::Zero();
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // shading normal, turned towards the camera
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  bool hit = false;
  std::uint32_t rays = 0;  // rays traced (intersection and shadow), for statistics
};

PathResult tracePath(const Scene& scene, Ray ray, Rng& rng, int max_bounces);

// Origin for rays leaving a surface at p on the side of the unit normal n: far enough to not hit the same surface
// again through rounding (relative to the coordinates' magnitude), close enough to keep contact shadows.
Eigen::Vector3f offsetFromSurface(const Eigen::Vector3f& p, const Eigen::Vector3f& n);

}  // namespace wobble::render
