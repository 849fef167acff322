// Stage 3 of the pass between bodies (body_collisions.h), its fail-safe: hits left after the collision impulses'
// rounds merge their particles into rigid impact zones (union-find) that move as rigid bodies with their linear and
// angular momentum (a zone holding a pinned particle stands still): Provot 1997, "Collision and self-collision
// handling in cloth model dedicated to design garments"; Harmon, Vouga, Tamstorf & Grinspun 2008, "Robust treatment
// of simultaneous collisions".
#pragma once
#include <algorithm>
#include <numeric>
#include <vector>

#include "sim/contact/candidates/candidates.h"
#include "sim/contact/node_motion.h"

namespace wobble::collision {

class ImpactZones {
 public:
  ImpactZones(const SurfaceNodes& nodes, NodeMotion& motion, const VecX& inv_mass)
      : nodes_(nodes), motion_(motion), inv_mass_(inv_mass) {}
  // No zones yet, over n particles.
  void reset(int n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  // Merges the hits' particles into zones, and moves every zone touched as a rigid body. Returns the largest's size.
  int rigidify(const Candidates& round, const std::vector<Contact>& hits, double h);
  // Each pass particle's zone, for the threads of a detection round (inOneZone).
  void findRoots(const SurfaceNodes& nodes) {
    root_.resize(parent_.size());
    for (const int p : nodes.pass_particles) root_[p] = find(p);
  }
  // Whether a pair's particles all lie in one zone (after findRoots).
  bool inOneZone(const SurfaceNodes& nodes, const Stencil& s) const {
    const int r = root_[nodes.node_particle[nodes.node_start[s.vertex[0]]]];
    for (const int k : s.vertex)
      for (int j = nodes.node_start[k]; j < nodes.node_start[k + 1]; ++j)
        if (root_[nodes.node_particle[j]] != r) return false;
    return true;
  }

 private:
  int find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  // The smaller root becomes the parent: zones are the same whatever the order of merges.
  void merge(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

  const SurfaceNodes& nodes_;
  NodeMotion& motion_;
  const VecX& inv_mass_;
  std::vector<int> parent_;
  std::vector<int> root_;  // find of each pass particle, for the threads of a detection round
};

}  // namespace wobble::collision
