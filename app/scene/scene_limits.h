// The limits a scene must keep, checked while it is read and before anything is allocated, so that no scene file
// can crash the program, exhaust memory or disk, or run for ever: each is an input error (exit 2) naming the key.
// docs/limits.md documents them.
#pragma once
#include <cstdint>
#include <string>

#include "image/png_io.h"
#include "sim/body.h"

namespace wobble {

inline constexpr std::int64_t kMaxFrames = 100'000;            // per run: 55 min of simulated time at 30 fps
inline constexpr double kMaxStepsPerFrame = 1e6;               // 1 / (fps dt): a frame is at most a million steps
inline constexpr int kMaxNestingDepth = 64;                    // TOML nesting ([ { and dotted keys), see toml_depth.h
inline constexpr std::uintmax_t kMaxSceneFileBytes = 1 << 20;  // a scene is a hand-written file of a few KB
inline constexpr int kMaxTextureSide = image::kMaxImageSide;   // pixels, width and height of a texture image
inline constexpr int kMaxEnvironmentSide = image::kMaxImageSide / 2;  // pixels, height of an environment map (2:1)
inline constexpr std::size_t kMaxNameLength = 64;                     // body, collider and scene names (identifier.h)

// Half of physical memory: the estimate below is an upper bound of the simulation's own data, and the renderer,
// the OS and other programs need the rest.
std::uint64_t defaultMemoryBudget();

// The budget of this process: --max-memory when given (max_memory_option.h), else the default.
void setMemoryBudget(std::uint64_t bytes);
std::uint64_t memoryBudget();

// Memory a scene will take, summed over its bodies and textures as they are read.
struct SceneEstimate {
  BodySize bodies;
  std::int64_t texture_pixels = 0;
  std::int64_t environment_pixels = 0;  // render.environment's map
  std::int64_t render_pixels = 0;       // camera resolution, when the scene renders images

  void add(const BodySize& b);
  // Upper bound in bytes: particle state and the integrator's stages, springs (twice: body and system, with
  // vector growth; implicit integrators add their sparse Jacobians), surfaces and a frame's OBJ text, textures,
  // and the render buffers of two frames (one rendering, one being written).
  std::uint64_t bytes(bool implicit_integrator) const;
  std::string describe(bool implicit_integrator) const;  // "27000000 particles, 423000000 springs: 30.1 GB"
};

// "1.5 GB", "300 MB" (powers of 1024).
std::string formatBytes(std::uint64_t bytes);

}  // namespace wobble
