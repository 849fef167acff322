// SurfaceHit: what a ray hit, in the terms shading needs.
//   t          ray parameter (distance, since ray directions are unit)
//   p          hit point (interpolated from the triangle's vertices, more accurate than origin + t dir)
//   ng         unit geometric normal as modelled: (p1 - p0) x (p2 - p0) for a triangle, outward for a sphere.
//              Not turned towards the ray.
//   ns         unit shading normal: interpolated vertex normals (ng where the mesh has none)
//   uv         interpolated texture coordinates
//   dpdu, dpdv how the point moves with u and v (the surface's UV parametrisation; zero where it has none), for
//              texture filtering: zero until Scene::uvDerivatives fills them
//   shape, primitive   the Scene's shape id and the triangle index within it (0 for a sphere)
//   material   the shape's material id
//   time       the ray's time (motion blur, scene.h): which pose of a moving shape was hit
//   dpdt       how the surface point moves over the whole shutter (per unit of ray time; zero for a still shape), for
//              the texture filter of a motion-blurred pixel
#pragma once
#include <Eigen/Core>

namespace wobble::render {

struct SurfaceHit {
  float t = 0;
  Eigen::Vector3f p, ng, ns;
  Eigen::Vector2f uv;
  Eigen::Vector3f dpdu = Eigen::Vector3f::Zero(), dpdv = Eigen::Vector3f::Zero();
  int shape = -1, primitive = -1, material = -1;
  float time = 0;
  Eigen::Vector3f dpdt = Eigen::Vector3f::Zero();
};

}  // namespace wobble::render
