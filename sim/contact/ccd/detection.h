// Stage 2 of the pass between bodies (body_collisions.h): continuous detection of the round's pairs along the
// trajectories (ccd.h); each hit gets an impulse that stops the approach (with at most a tenth of it back as
// separation), in a fixed order.
#pragma once
#include <vector>

#include "sim/contact/candidates/candidates.h"
#include "sim/contact/candidates/skins.h"
#include "sim/contact/ccd/impact_zones.h"
#include "sim/contact/node_motion.h"

namespace wobble::collision {

class Detection {
 public:
  Detection(const SurfaceNodes& nodes, NodeMotion& motion, const VecX& inv_mass, const Skins& skins, bool parallel)
      : nodes_(nodes), motion_(motion), inv_mass_(inv_mass), skins_(skins), parallel_(parallel) {}
  // Continuous detection over the pairs with a particle moved since the last round (every pair when all is set).
  // With zones: pairs inside one impact zone are skipped, as its motion x0 + s h (v + w x r) is an invertible
  // affine map of the zone for every s (det(I + s h [w]x) = 1 + s^2 h^2 |w|^2), which keeps four points off a plane.
  std::vector<Contact> detect(Candidates& round, ImpactZones* zones, bool all);
  // An impulse on each hit still approaching, in order.
  void impulses(const Candidates& round, const std::vector<Contact>& hits, double h);

 private:
  const SurfaceNodes& nodes_;
  NodeMotion& motion_;
  const VecX& inv_mass_;
  const Skins& skins_;
  bool parallel_;
};

}  // namespace wobble::collision
