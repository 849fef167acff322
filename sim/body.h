// A body: its particles' initial state and masses, its springs and its surface, in body-local indices.
// Builders (bodies/jelly.h, bodies/cloth.h) make them; MassSpringSystem joins several into one flat state.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sim/collision/params.h"
#include "sim/springs.h"
#include "sim/surface.h"
#include "sim/types.h"

namespace wobble {

struct Body {
  std::string name;
  std::string kind;          // "jelly", "cloth"
  VecX x, v;                 // initial positions and velocities, 3 per particle
  VecX mass;                 // per particle
  std::vector<bool> pinned;  // a pinned particle has inverse mass 0 and never moves
  double drag = 0;           // viscous air drag coefficient: f = -drag v on each particle
  Springs springs;
  SurfaceMesh surface;
  collision::SurfaceParams contact;  // contact with other bodies and itself (sim/collision/)

  int particleCount() const { return static_cast<int>(mass.size()); }
};

// What a builder will make, counted in 64 bits before anything is allocated (app/scene_limits.h budgets it).
struct BodySize {
  std::int64_t particles = 0, springs = 0, surface_vertices = 0, triangles = 0;
};

// Particle indices are int throughout the simulator (and 3 per particle in flat vectors): builders refuse more.
inline constexpr std::int64_t kMaxBodyParticles = (std::int64_t{1} << 31) / 3 - 1;

}  // namespace wobble
