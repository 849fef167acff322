#include "sim/bodies/cloth.h"

#include <stdexcept>

#include "sim/bodies/lattice.h"

namespace wobble {
namespace {

constexpr LatticeOffset kClothOffsets[] = {
    {{1, 0, 0}, SpringType::Structural}, {{0, 1, 0}, SpringType::Structural}, {{1, 1, 0}, SpringType::Shear},
    {{1, -1, 0}, SpringType::Shear},     {{2, 0, 0}, SpringType::Bending},    {{0, 2, 0}, SpringType::Bending},
};

}  // namespace

std::vector<int> clothPinSet(std::string_view name, int nx, int ny) {
  if (name == "corners") return {0, nx - 1, nx * (ny - 1), nx * ny - 1};
  if (name == "top-edge") {
    std::vector<int> row(nx);
    for (int i = 0; i < nx; ++i) row[i] = i;
    return row;
  }
  throw std::invalid_argument("unknown pin set '" + std::string(name) + "' (allowed: corners, top-edge)");
}

BodySize clothSize(std::int64_t nx, std::int64_t ny) {
  return {nx * ny, latticeSpringCount({nx, ny, 1}, kClothOffsets), nx * ny, 2 * (nx - 1) * (ny - 1)};
}

Body buildCloth(const std::string& name, const ClothParams& p) {
  if (std::int64_t(p.nx) * p.ny > kMaxBodyParticles)
    throw std::length_error("cloth '" + name + "': " + std::to_string(p.nx) + " x " + std::to_string(p.ny) +
                            " particles are too many");
  const int count = p.nx * p.ny;
  Body body = particleBody(name, "cloth", count, p.mass);
  body.drag = p.drag;
  for (int j = 0; j < p.ny; ++j)
    for (int i = 0; i < p.nx; ++i) {
      const double s = (double(i) / (p.nx - 1) - 0.5) * p.size_x, t = (double(j) / (p.ny - 1) - 0.5) * p.size_y;
      const int id = i + p.nx * j;
      particle(body.x, id) = p.center + (p.hanging ? Vec3(s, -t, 0) : Vec3(s, 0, t));
      particle(body.v, id) = p.velocity;
      body.surface.particle.push_back(id);
      body.surface.uv.emplace_back(float(i) / float(p.nx - 1), 1.0f - float(j) / float(p.ny - 1));
    }
  for (int id : p.pinned) {
    if (id < 0 || id >= count)
      throw std::invalid_argument("pinned particle " + std::to_string(id) + " out of range [0, " +
                                  std::to_string(count - 1) + "]");
    body.pinned[id] = true;
    particle(body.v, id).setZero();
  }
  addLatticeSprings({p.nx, p.ny, 1}, kClothOffsets, body.x, p.ks, p.kd, body.springs);
  for (int j = 0; j + 1 < p.ny; ++j)
    for (int i = 0; i + 1 < p.nx; ++i) {
      const int a = i + p.nx * j, b = a + 1, c = a + 1 + p.nx, d = a + p.nx;
      body.surface.triangles.push_back({a, d, c});  // (d - a) x (c - a) points to the front
      body.surface.triangles.push_back({a, c, b});
    }
  return body;
}

}  // namespace wobble
