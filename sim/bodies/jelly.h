// Jelly: an n x n x n cube lattice of particles joined by structural (axis neighbours), shear (face and body
// diagonals) and bending (axis neighbours two apart) springs, rest length = initial distance.
//
// Parameters (course-framework defaults):
//   n = 10          particles along each edge (>= 2; bending springs need n >= 3)
//   size = 4        edge length (m)
//   mass = 1        mass of each particle (kg)
//   ks = 1400, kd = 50   spring and damper coefficients, every spring type
//   center          lattice centre; default puts the lowest particles at y = 6.78 as in the course framework
//   rotation_axis, rotation_deg   initial rotation about the centre (the framework used the axis (1, 0, 1))
//   velocity        initial velocity of every particle
// Surface: the six outer faces, each with its own n x n vertices and UVs spanning [0,1]^2, so a texture shows once
// per face, upright on the four side faces.
#pragma once
#include <span>
#include <string>

#include "sim/bodies/lattice.h"
#include "sim/body.h"

namespace wobble {

struct JellyParams {
  int n = 10;
  double size = 4;
  double mass = 1;
  double ks = 1400, kd = 50;
  Vec3 center{0, 8.78, 0};
  Vec3 rotation_axis{1, 0, 1};
  double rotation_deg = 0;
  Vec3 velocity = Vec3::Zero();
};

// The lattice offsets the jelly links (structural, shear, bending), shared with the mesh jelly.
std::span<const LatticeOffset> jellyOffsets();

// n^3 particles: for n up to 2^19 (no overflow).
BodySize jellySize(std::int64_t n);

// Throws std::length_error for more than kMaxBodyParticles particles.
Body buildJelly(const std::string& name, const JellyParams& p);

}  // namespace wobble
