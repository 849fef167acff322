// Analytic scene objects besides simulator meshes. Quads and boxes become small triangle meshes (they are flat,
// so nothing is lost); the sphere stays analytic (Embree sphere primitive), so its silhouette and shading are smooth.
//
//   Quad    a finite square in a plane: center, normal (any length), size (side length), uv_repeat (texture tiles
//           across the side; 1 = once). Its u axis is normal x (0,0,1) (or normal x (0,1,0) when the normal is along
//           z), v = normal x u, so on a floor (normal +y) u runs along +x and v along -z.
//   Box     an axis-aligned box: center, size (full extents). Each face has UVs over [0,1]^2.
//   Sphere  center, radius (> 0). UVs: u = longitude around +y, v = latitude (0 at the bottom, 1 at the top).
#pragma once
#include <Eigen/Core>

#include "render/mesh.h"

namespace wobble::render {

struct Quad {
  Eigen::Vector3f center{0, 0, 0};
  Eigen::Vector3f normal{0, 1, 0};
  float size = 10;
  float uv_repeat = 1;
};

struct Box {
  Eigen::Vector3f center{0, 0, 0};
  Eigen::Vector3f size{1, 1, 1};
};

struct Sphere {
  Eigen::Vector3f center{0, 0, 0};
  float radius = 1;
};

// Throw std::invalid_argument (naming `name`) on non-finite or non-positive parameters.
TriangleMesh quadMesh(const std::string& name, const Quad& quad);
TriangleMesh boxMesh(const std::string& name, const Box& box);
void checkSphere(const std::string& name, const Sphere& sphere);

}  // namespace wobble::render
