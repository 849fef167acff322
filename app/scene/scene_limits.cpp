#include "app/scene/scene_limits.h"

#include <unistd.h>

#include <cstdio>

namespace wobble {
namespace {

// Bytes per item, generous: Eigen vectors of 3 doubles per particle for x, v and up to 13 integrator stages (rk45)
// plus mass, inverse mass, drag and the initial state; springs as structure of arrays (33 B, twice, 2x growth);
// implicit Jacobians: 4 blocks of 3x3 doubles for dfdx and dfdv as triplets (16 B) and compressed (12 B).
constexpr std::uint64_t kParticleBytes = 16 * 24 + 8 * 8;
constexpr std::uint64_t kSpringBytes = 2 * 2 * 33;
constexpr std::uint64_t kImplicitSpringBytes = 2 * 36 * (16 + 12);
// A vertex: particle index and UV, its position and normal per frame, and ~90 bytes of OBJ text (v, vn, vt).
constexpr std::uint64_t kVertexBytes = 12 + 24 + 90;
constexpr std::uint64_t kTriangleBytes = 12 + 40;  // indices and an OBJ "f" line
constexpr std::uint64_t kTexelBytes = 4 + 16;      // 8-bit RGBA as read, and the renderer's float RGBA copy
// An environment texel: float RGBA as read, the map's float RGB, its sampling weight (twice while built) and cdf.
constexpr std::uint64_t kEnvironmentTexelBytes = 16 + 12 + 3 * 4;
// Per image pixel: the film's layers (64 B) and adaptive state (32), the denoiser's padded planes (about 120) and
// its output (12), the 8-bit image and its PNG (6): about 240 B, and two frames are alive at once.
constexpr std::uint64_t kRenderPixelBytes = 2 * 256;

}  // namespace

std::uint64_t defaultMemoryBudget() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return std::uint64_t{4} << 30;  // unknown: a modest 4 GB
  return std::uint64_t(pages) * std::uint64_t(page) / 2;
}

namespace {
std::uint64_t budget_override = 0;
}  // namespace

void setMemoryBudget(std::uint64_t bytes) { budget_override = bytes; }

std::uint64_t memoryBudget() { return budget_override > 0 ? budget_override : defaultMemoryBudget(); }

void SceneEstimate::add(const BodySize& b) {
  bodies.particles += b.particles;
  bodies.springs += b.springs;
  bodies.surface_vertices += b.surface_vertices;
  bodies.triangles += b.triangles;
}

std::uint64_t SceneEstimate::bytes(bool implicit_integrator) const {
  // Counts here are bounded by the readers (int keys, at most 2^31 per axis): products stay far below 2^64 / 2^12.
  return std::uint64_t(bodies.particles) * kParticleBytes +
         std::uint64_t(bodies.springs) * (kSpringBytes + (implicit_integrator ? kImplicitSpringBytes : 0)) +
         std::uint64_t(bodies.surface_vertices) * kVertexBytes + std::uint64_t(bodies.triangles) * kTriangleBytes +
         std::uint64_t(texture_pixels) * kTexelBytes + std::uint64_t(environment_pixels) * kEnvironmentTexelBytes +
         std::uint64_t(render_pixels) * kRenderPixelBytes;
}

std::string SceneEstimate::describe(bool implicit_integrator) const {
  return std::to_string(bodies.particles) + " particles, " + std::to_string(bodies.springs) + " springs" +
         (texture_pixels > 0 ? ", " + std::to_string(texture_pixels) + " texture pixels" : "") +
         (environment_pixels > 0 ? ", " + std::to_string(environment_pixels) + " environment pixels" : "") +
         (render_pixels > 0 ? ", " + std::to_string(render_pixels) + " image pixels" : "") + ": about " +
         formatBytes(bytes(implicit_integrator));
}

std::string formatBytes(std::uint64_t bytes) {
  const char* units[] = {"B", "KB", "MB", "GB", "TB", "PB", "EB"};
  double value = double(bytes);
  int unit = 0;
  while (value >= 1024 && unit < 6) value /= 1024, ++unit;
  char text[32];
  std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", value, units[unit]);
  return text;
}

}  // namespace wobble
