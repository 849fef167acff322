// A weighted sum of particles, sum_i w_i y_(p_i) of a flat 3-per-particle vector y: the relative position (or
// velocity) of two surface elements in contact between bodies (Bridson, Fedkiw & Anderson 2002's stencils). Four
// particles for a point-triangle or edge-edge pair of surfaces over particles; up to 32 when the elements' vertices
// are themselves blends of particles (a mesh jelly's model vertices, each the trilinear blend of its lattice cell's 8
// particles: sim/weighted_points.h), each particle once with its weights summed. A fixed capacity, not a vector: the
// stencils are built and copied every step and must not allocate.
#pragma once
#include <array>

#include "sim/types.h"

namespace wobble {

struct WeightedStencil {
  static constexpr int kCapacity = 32;
  // Entries past size are never read: a user-provided constructor, so that a vector's resize (value-initialization)
  // does not zero the whole capacity of every stencil (backward Euler's pairs of a collapsed cloth: 50 MB a step).
  WeightedStencil() {}
  int size = 0;
  std::array<int, kCapacity> particle;
  std::array<double, kCapacity> w;

  // Adds weight to particle p's (a new entry if p is not in yet; the capacity must suffice).
  void add(int p, double weight) {
    for (int i = 0; i < size; ++i)
      if (particle[i] == p) {
        w[i] += weight;
        return;
      }
    particle[size] = p;
    w[size++] = weight;
  }
  // sum_i w_i y_(p_i).
  Vec3 sum(const VecX& y) const {
    Vec3 r = Vec3::Zero();
    for (int i = 0; i < size; ++i) r += w[i] * wobble::particle(y, particle[i]);
    return r;
  }
  // sum_i w_i^2 m_i^-1: the inverse of the effective mass of the sum (0 when every particle in it is pinned).
  double inverseMass(const VecX& inverse_mass) const {
    double s = 0;
    for (int i = 0; i < size; ++i) s += w[i] * w[i] * inverse_mass[particle[i]];
    return s;
  }
  // out_(p_i) += w_i g: a force (or impulse) g on the sum, handed to its particles.
  void spread(const Vec3& g, VecX& out) const {
    for (int i = 0; i < size; ++i) wobble::particle(out, particle[i]) += w[i] * g;
  }
};

}  // namespace wobble
