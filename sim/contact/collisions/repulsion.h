// Stage 1 of the pass between bodies (body_collisions.h): each point-triangle and edge-edge pair within the contact
// thickness at the step's start gets an inelastic impulse that stops its approach, a repulsion capped by a spring of
// the bodies' stiffness over the thickness left, and Coulomb friction on its tangential relative velocity (Bridson,
// Fedkiw & Anderson 2002, section 7.2).
#pragma once
#include <vector>

#include "sim/contact/candidates/candidates.h"
#include "sim/contact/candidates/skins.h"
#include "sim/contact/node_motion.h"
#include "sim/contact/stats.h"

namespace wobble::collision {

class Repulsion {
 public:
  Repulsion(const SurfaceNodes& nodes, NodeMotion& motion, const VecX& inv_mass, Skins& skins, bool parallel)
      : nodes_(nodes), motion_(motion), inv_mass_(inv_mass), skins_(skins), parallel_(parallel) {}
  // Repulsion and friction for the round's pairs within the thickness at the start, counted in stats (only counted
  // without impulses). Fills the round's nearest points at the start for the continuous test that follows.
  void repel(Candidates& round, double h, Stats& stats, bool impulses);

 private:
  double weightNorm(const Stencil& s, const std::array<double, 4>& w) const;

  const SurfaceNodes& nodes_;
  NodeMotion& motion_;
  const VecX& inv_mass_;
  Skins& skins_;
  bool parallel_;
  std::vector<long> contact_counts_;  // repel's per chunk, kept from step to step
};

}  // namespace wobble::collision
