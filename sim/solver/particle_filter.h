// Baraff & Witkin's constraint filter (1998, "Large Steps in Cloth Simulation", section 5.3), one 3x3 block per
// particle: S_p = I for a free particle, 0 for a held one, I - n n^T for one constrained along a normal n (a contact:
// its velocity change along n is prescribed), d d^T for one constrained along two independent normals n1, n2 (two
// contacts at once: only d = n1 x n2 / |n1 x n2|, the line both surfaces leave free, is left), 0 for three or more
// independent normals. S_p is the orthogonal projection onto the directions every one of the particle's normals
// leaves free: symmetric, idempotent, S_p n_i = 0. Normals within kParallel of the span of the ones before count as
// one of them (their constraint is the same to that accuracy, and a near-singular pair would make the prescribed
// part ill-conditioned: contact/constraints/constraints.h).
#pragma once
#include <cstdint>
#include <vector>

#include "sim/types.h"

namespace wobble {

class ParticleFilter {
 public:
  enum Kind : std::uint8_t { Free, Held, Normal, Line };
  // |n1 x n2| (the sine of their angle) below which a second normal counts as the first, and |d . n3| (the sine of
  // n3's angle to the plane of n1 and n2) below which a third counts as in their span.
  static constexpr double kParallel = 0.05;

  // Every particle free, except those with inverse mass 0: held.
  void reset(const VecX& inverse_mass);
  // Constrains p along the unit normal as well as along what it was constrained along before (the intersection).
  void constrain(int p, const Vec3& normal) {
    if (kind_[p] != Free) return intersect(p, normal);
    ++constrained_;
    kind_[p] = Normal;
    particle(direction_, p) = normal;
  }
  // Holds p in every direction (S_p = 0: all of its velocity change prescribed, e.g. by static friction).
  void hold(int p) {
    if (kind_[p] == Free) ++constrained_;
    kind_[p] = Held;
  }
  Kind kind(int p) const { return Kind(kind_[p]); }
  const std::vector<std::uint8_t>& kinds() const { return kind_; }  // per particle its Kind
  Vec3 normal(int p) const { return particle(direction_, p); }      // Normal: the constrained direction
  Vec3 direction(int p) const { return particle(direction_, p); }   // Line: the free direction d
  bool anyConstrained() const { return constrained_ > 0; }
  // S_p as a matrix.
  Eigen::Matrix3d matrix(int p) const;

  Vec3 apply(int p, const Vec3& y) const {
    switch (kind_[p]) {
      case Free:
        return y;
      case Normal: {
        const Vec3 n = particle(direction_, p);
        return y - n.dot(y) * n;
      }
      case Line: {
        const Vec3 d = particle(direction_, p);
        return d.dot(y) * d;
      }
      default:
        return Vec3::Zero();
    }
  }
  void apply(VecX& y, int begin, int end) const {
    for (int p = begin; p < end; ++p) particle(y, p) = apply(p, particle(y, p));
  }
  // y's component that S removes: (I - S) y.
  Vec3 removed(int p, const Vec3& y) const { return y - apply(p, y); }

 private:
  void intersect(int p, const Vec3& normal);

  std::vector<std::uint8_t> kind_;
  VecX direction_;  // Normal: n; Line: d
  int constrained_ = 0;
};

}  // namespace wobble
