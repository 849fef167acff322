// Baraff & Witkin's constraint filter, one 3x3 block per particle: S_p = I for a free particle, 0 for a held one
// (pinned), I - n n^T for one constrained along a normal n (a contact: its velocity change along n is prescribed).
#pragma once
#include <cstdint>
#include <vector>

#include "sim/types.h"

namespace wobble {

class ParticleFilter {
 public:
  enum Kind : std::uint8_t { Free, Held, Normal };

  // Every particle free, except those with inverse mass 0: held.
  void reset(const VecX& inverse_mass);
  void constrain(int p, const Vec3& normal) {
    constrained_ += kind_[p] != Normal;
    kind_[p] = Normal;
    particle(normal_, p) = normal;
  }
  Kind kind(int p) const { return Kind(kind_[p]); }
  Vec3 normal(int p) const { return particle(normal_, p); }
  bool anyConstrained() const { return constrained_ > 0; }

  Vec3 apply(int p, const Vec3& y) const {
    switch (kind_[p]) {
      case Free:
        return y;
      case Held:
        return Vec3::Zero();
      default: {
        const Vec3 n = particle(normal_, p);
        return y - n.dot(y) * n;
      }
    }
  }
  void apply(VecX& y, int begin, int end) const {
    for (int p = begin; p < end; ++p) particle(y, p) = apply(p, particle(y, p));
  }
  // y's component that S removes: (I - S) y.
  Vec3 removed(int p, const Vec3& y) const { return y - apply(p, y); }

 private:
  std::vector<std::uint8_t> kind_;
  VecX normal_;
  int constrained_ = 0;
};

}  // namespace wobble
