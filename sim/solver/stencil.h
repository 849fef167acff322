// A weighted sum of particles, sum_i w_i y_(p_i) of a flat 3-per-particle vector y: the relative position (or
// velocity) of two surface elements in contact between bodies (Bridson, Fedkiw & Anderson 2002's stencils). Four
// particles for a point-triangle or edge-edge pair of surfaces over particles; up to 32 when the elements' vertices
// are themselves blends of particles (a mesh jelly's model vertices, each the trilinear blend of its lattice cell's 8
// particles: sim/contact/colliders/weighted_points.h), each particle once with its weights summed. Four in place and
// the rest on the heap, not a vector: the stencils of surfaces over particles are built and copied every step and must
// not allocate.
#pragma once
#include <algorithm>
#include <array>

#include "sim/types.h"

namespace wobble {

struct WeightedStencil {
  static constexpr int kCapacity = 32;
  // Entries held in place: the four of a pair of surfaces over particles. A stencil of more (a mesh jelly's) moves
  // them to the heap. Backward Euler lists some 100 000 pairs a step on a cloth collapsed on itself (690 000 at 256 x
  // 256), each written, copied and read several times: room for all 32 in place made a pair 472 bytes, 152 now.
  static constexpr int kInline = 4;
  // Entries past size are never read, nor initialized: a user-provided constructor, so that value-initializing a
  // stencil writes its size and pointers only.
  WeightedStencil() {}
  WeightedStencil(const WeightedStencil& o) { copyEntries(o); }
  WeightedStencil(WeightedStencil&& o) noexcept { take(o); }
  WeightedStencil& operator=(const WeightedStencil& o) {
    if (this != &o) copyEntries(o);
    return *this;
  }
  WeightedStencil& operator=(WeightedStencil&& o) noexcept {
    if (this != &o) release(), take(o);
    return *this;
  }
  ~WeightedStencil() { release(); }

  int size = 0;
  // particle[i], w[i] for i < size: in place (kInline) or on the heap (kCapacity).
  int* particle = inline_particle_;
  double* w = inline_w_;

  // Adds weight to particle p's (a new entry if p is not in yet; the capacity must suffice).
  void add(int p, double weight) {
    for (int i = 0; i < size; ++i)
      if (particle[i] == p) {
        w[i] += weight;
        return;
      }
    if (size == kInline && !onHeap()) moveToHeap();
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

 private:
  bool onHeap() const { return particle != inline_particle_; }
  // Room for kCapacity entries on the heap, with the entries so far.
  void moveToHeap() {
    int* heap_particle = new int[kCapacity];
    double* heap_w = new double[kCapacity];
    std::copy(particle, particle + size, heap_particle);
    std::copy(w, w + size, heap_w);
    particle = heap_particle, w = heap_w;
  }
  void release() {
    if (!onHeap()) return;
    delete[] particle;
    delete[] w;
    particle = inline_particle_, w = inline_w_;
  }
  // This stencil's entries become o's (its heap kept when it has one; taken when o has more than fit in place).
  void copyEntries(const WeightedStencil& o) {
    if (o.size > kInline && !onHeap()) moveToHeap();
    size = o.size;
    std::copy(o.particle, o.particle + o.size, particle);
    std::copy(o.w, o.w + o.size, w);
  }
  // This stencil (in place) takes o's heap, or copies o's entries held in place.
  void take(WeightedStencil& o) {
    if (!o.onHeap()) return copyEntries(o);
    particle = o.particle, w = o.w, size = o.size;
    o.particle = o.inline_particle_, o.w = o.inline_w_, o.size = 0;
  }
  int inline_particle_[kInline];
  double inline_w_[kInline];
};

}  // namespace wobble
