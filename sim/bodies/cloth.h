// Cloth: an nx x ny grid of particles with structural, shear (both diagonals) and bending (two apart) springs.
//
// Parameters (course-framework defaults):
//   nx = 25, ny = 25   particles along the two edges (>= 2 each)
//   size = [4, 4]      extent along the two edges (m)
//   center = [0, 1, 0]
//   hanging = false    false: horizontal in x-z; true: vertical in x-y (a curtain), row 0 at the top
//   mass = 1           per particle (kg);  ks = 20000, kd = 750;  drag = 3.4e-4 (viscous air drag)
//   pinned             particle indices (i + nx j) and/or names: "corners", "top-edge" (row j = 0: the -z edge of a
//                      horizontal cloth, the top of a hanging one)
//   velocity           initial velocity of every particle
// Surface: the grid itself, one vertex per particle, UVs spanning [0,1]^2, front face toward +y (horizontal) or +z.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "sim/body.h"

namespace wobble {

struct ClothParams {
  int nx = 25, ny = 25;
  double size_x = 4, size_y = 4;
  Vec3 center{0, 1, 0};
  bool hanging = false;
  double mass = 1;
  double ks = 20000, kd = 750;
  double drag = 3.4e-4;
  std::vector<int> pinned;
  Vec3 velocity = Vec3::Zero();
};

// Indices of a named particle set; throws std::invalid_argument naming the allowed names.
std::vector<int> clothPinSet(std::string_view name, int nx, int ny);

BodySize clothSize(std::int64_t nx, std::int64_t ny);

// Throws std::length_error for more than kMaxBodyParticles particles.
Body buildCloth(const std::string& name, const ClothParams& p);

}  // namespace wobble
