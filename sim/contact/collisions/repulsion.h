// Stage 1 of the pass between bodies (body_collisions.h): each point-triangle and edge-edge pair within the contact
// thickness at the step's start gets an inelastic impulse that stops its approach, a repulsion capped by a spring of
// the bodies' stiffness over the thickness left, and Coulomb friction on its tangential relative velocity (Bridson,
// Fedkiw & Anderson 2002, section 7.2). For an explicit integrator (ahead) also each pair apart at the start that ends
// within the thickness, its distance along its nearest points' direction there too, is stopped where it reaches it;
// and after the pass (settle) the approach that the end velocities of those pairs keep is stopped, positions untouched
// (Guendelman, Bridson & Fedkiw 2003: contact on the velocity after its update).
#pragma once
#include <vector>

#include "sim/contact/candidates/candidates.h"
#include "sim/contact/candidates/skins.h"
#include "sim/contact/node_motion.h"
#include "sim/contact/stats.h"
#include "sim/solver/stencil.h"

namespace wobble::collision {

class Repulsion {
 public:
  Repulsion(const SurfaceNodes& nodes, NodeMotion& motion, const VecX& inv_mass, Skins& skins, bool parallel)
      : nodes_(nodes), motion_(motion), inv_mass_(inv_mass), skins_(skins), parallel_(parallel) {}
  // Repulsion and friction for the round's pairs within the thickness at the start, counted in stats (only counted
  // without impulses), and with ahead those apart that end within it. Fills the round's nearest points at the start
  // for the continuous test that follows.
  void repel(Candidates& round, double h, Stats& stats, bool impulses, bool ahead);
  // After the pass has written the step's end velocities v: the approach of repel's pairs in v, stopped by inelastic
  // impulses on v alone (projected Gauss-Seidel to convergence), so that a pair stopped over the step does not keep
  // the approach its load added within it (half the load's acceleration times h).
  void settle(VecX& v) const;

 private:
  double weightNorm(const Stencil& s, const std::array<double, 4>& w) const;

  const SurfaceNodes& nodes_;
  NodeMotion& motion_;
  const VecX& inv_mass_;
  Skins& skins_;
  bool parallel_;
  std::vector<long> contact_counts_;  // repel's per chunk, kept from step to step
  struct Pressed {                    // a pair repel gave impulses, over its particles
    WeightedStencil stencil;
    Vec3 normal;
    double denom;  // sum w^2 / m
  };
  std::vector<Pressed> pressed_;  // repel's, for settle
  std::vector<int> listed_;       // repel's candidates from the step's lists
};

}  // namespace wobble::collision
