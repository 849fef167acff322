#include "sim/surface.h"

namespace wobble {

SurfaceFrame evaluateSurface(const SurfaceMesh& mesh, const VecX& x, int first_particle) {
  SurfaceFrame frame;
  const std::size_t n = mesh.vertexCount();
  frame.positions.resize(n);
  frame.normals.assign(n, Eigen::Vector3f::Zero());
  // Accumulate in double: float cross products of nearly parallel edges lose the normal's direction.
  std::vector<Vec3> pos(n), nrm(n, Vec3::Zero());
  if (mesh.embedded.empty()) {
    for (std::size_t i = 0; i < n; ++i) pos[i] = particle(x, first_particle + mesh.particle[i]);
  } else {
    // Each embedded point once (seam vertices share one), then its vertices copy it.
    std::vector<Vec3> point(mesh.embedded.size());
    for (std::size_t e = 0; e < point.size(); ++e) {
      const EmbeddedPoint& ep = mesh.embedded[e];
      Vec3 sum = Vec3::Zero();
      for (int c = 0; c < 8; ++c) sum += ep.weight[c] * particle(x, first_particle + ep.particle[c]);
      point[e] = sum;
    }
    for (std::size_t i = 0; i < n; ++i) pos[i] = point[mesh.particle[i]];
  }
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
