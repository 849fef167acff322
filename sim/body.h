// A body: its particles' initial state and masses, its springs and its surface, in body-local indices.
// Builders (bodies/jelly.h, bodies/cloth.h) make them; MassSpringSystem joins several into one flat state.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sim/springs.h"
#include "sim/surface.h"
#include "sim/types.h"

namespace wobble {

// How a body's surface meets other bodies and itself, read from its scene table (scenes/README.md); contact between
// bodies (sim/contact/) reads it.
struct SurfaceContact {
  double thickness = 0.02;  // m: surfaces are kept this far apart (the larger of two bodies' values between them)
  double friction = 0.3;    // Coulomb coefficient (the mean of two bodies' values between them)
  bool self_contact = false;
};

struct Body {
  std::string name;
  std::string kind;          // "jelly", "cloth"
  VecX x, v;                 // initial positions and velocities, 3 per particle
  VecX mass;                 // per particle
  std::vector<bool> pinned;  // a pinned particle has inverse mass 0 and never moves
  double drag = 0;           // viscous air drag coefficient: f = -drag v on each particle
  Springs springs;
  SurfaceMesh surface;
  SurfaceContact contact;

  int particleCount() const { return static_cast<int>(mass.size()); }
};

// What a builder will make, counted in 64 bits before anything is allocated (app/scene_limits.h budgets it).
struct BodySize {
  std::int64_t particles = 0, springs = 0, surface_vertices = 0, triangles = 0;
};

// Particle indices are int throughout the simulator (and 3 per particle in flat vectors): builders refuse more.
inline constexpr std::int64_t kMaxBodyParticles = (std::int64_t{1} << 31) / 3 - 1;

}  // namespace wobble
