#include "sim/surface.h"

namespace wobble {

SurfaceFrame evaluateSurface(const SurfaceMesh& mesh, const VecX& x, int first_particle) {
  SurfaceFrame frame;
  const std::size_t n = mesh.vertexCount();
  frame.positions.resize(n);
  frame.normals.assign(n, Eigen::Vector3f::Zero());
  // Accumulate in double: float cross products of nearly parallel edges lose the normal's direction.
  std::vector<Vec3> pos(n), nrm(n, Vec3::Zero());
  for (std::size_t i = 0; i < n; ++i) pos[i] = particle(x, first_particle + mesh.particle[i]);
  for (const auto& t : mesh.triangles) {
    const Vec3 area_normal = (pos[t[1]] - pos[t[0]]).cross(pos[t[2]] - pos[t[0]]);  // |.| = 2 * area
    for (int k : t) nrm[k] += area_normal;
  }
  for (std::size_t i = 0; i < n; ++i) {
    frame.positions[i] = pos[i].cast<float>();
    const double len = nrm[i].norm();
    frame.normals[i] = (len > 0 ? Vec3(nrm[i] / len) : Vec3::UnitY()).cast<float>();
  }
  return frame;
}

}  // namespace wobble
