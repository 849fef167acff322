#include "sim/bodies/jelly.h"

#include <stdexcept>

#include <Eigen/Geometry>

#include "sim/bodies/lattice.h"

namespace wobble {
namespace {

constexpr LatticeOffset kJellyOffsets[] = {
    {{1, 0, 0}, SpringType::Structural}, {{0, 1, 0}, SpringType::Structural}, {{0, 0, 1}, SpringType::Structural},
    {{1, 1, 0}, SpringType::Shear},      {{1, -1, 0}, SpringType::Shear},     {{1, 0, 1}, SpringType::Shear},
    {{1, 0, -1}, SpringType::Shear},     {{0, 1, 1}, SpringType::Shear},      {{0, 1, -1}, SpringType::Shear},
    {{1, 1, 1}, SpringType::Shear},      {{1, 1, -1}, SpringType::Shear},     {{1, -1, 1}, SpringType::Shear},
    {{1, -1, -1}, SpringType::Shear},    {{2, 0, 0}, SpringType::Bending},    {{0, 2, 0}, SpringType::Bending},
    {{0, 0, 2}, SpringType::Bending},
};

// A cube face as a grid: lattice point of face coordinates (r, u) is origin + r * right + u * up, in lattice
// steps; right x up is the outward normal, up is +y on the side faces so textures stand upright.
struct Face {
  Eigen::Vector3i origin, right, up;  // origin in units of (n - 1)
};

constexpr int kFaceCount = 6;
const Face kFaces[kFaceCount] = {
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   // +z: right +x, up +y
    {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}},  // -z: right -x
    {{1, 0, 1}, {0, 0, -1}, {0, 1, 0}},  // +x: right -z
    {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}},   // -x: right +z
    {{0, 1, 1}, {1, 0, 0}, {0, 0, -1}},  // +y: right +x, up -z
    {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},   // -y: right +x, up +z
};

SurfaceMesh jellySurface(int n) {
  SurfaceMesh mesh;
  const auto index = [n](const Eigen::Vector3i& p) { return p.x() + n * (p.y() + n * p.z()); };
  for (const Face& f : kFaces) {
    const int base = static_cast<int>(mesh.vertexCount());
    for (int u = 0; u < n; ++u)
      for (int r = 0; r < n; ++r) {
        mesh.particle.push_back(index(f.origin * (n - 1) + r * f.right + u * f.up));
        mesh.uv.emplace_back(float(r) / float(n - 1), float(u) / float(n - 1));
      }
    for (int u = 0; u + 1 < n; ++u)
      for (int r = 0; r + 1 < n; ++r) {
        const int a = base + r + n * u, b = a + 1, c = a + 1 + n, d = a + n;
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      }
  }
  return mesh;
}

}  // namespace

std::span<const LatticeOffset> jellyOffsets() { return kJellyOffsets; }

BodySize jellySize(std::int64_t n) {
  return {n * n * n, latticeSpringCount({n, n, n}, kJellyOffsets), kFaceCount * n * n,
          kFaceCount * 2 * (n - 1) * (n - 1)};
}

Body buildJelly(const std::string& name, const JellyParams& p) {
  if (double(p.n) * p.n * p.n > double(kMaxBodyParticles))
    throw std::length_error("jelly '" + name + "': n = " + std::to_string(p.n) + " gives too many particles");
  const int n = p.n, count = n * n * n;
  Body body = particleBody(name, "jelly", count, p.mass);

  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(p.rotation_deg * EIGEN_PI / 180, p.rotation_axis.normalized()).toRotationMatrix();
  const double spacing = p.size / (n - 1), half = (n - 1) / 2.0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int id = i + n * (j + n * k);
        particle(body.x, id) = p.center + rotation * (spacing * Vec3(i - half, j - half, k - half));
        particle(body.v, id) = p.velocity;
      }
  addLatticeSprings({n, n, n}, kJellyOffsets, body.x, p.ks, p.kd, body.springs);
  body.surface = jellySurface(n);
  return body;
}

}  // namespace wobble
