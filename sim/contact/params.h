// The caps a scene's [contact] table sets for contact between bodies (sim/contact/collisions/body_collisions.h); what
// each body sets is its Body::contact (sim/body.h).
#pragma once

namespace wobble::collision {

// The caps of the [contact] table of a scene.
struct Settings {
  int ccd_iterations = 8;    // rounds of collision impulses before impact zones
  int zone_iterations = 64;  // rounds of impact zones before the pass gives up
  // Halvings of a step the pass failed on: the step is taken again from its start as two halves, each of them so
  // again if the pass fails on it, down to a 2^-split_steps part of the step; only then the run stops.
  int split_steps = 4;
  // Not scene keys: the most candidate pairs a step's broad phase may list, the larger of candidates_per_vertex per
  // surface vertex (about 40 where a cloth lies in four layers on itself) and min_candidates (8 million: about 1 GB,
  // at some 120 bytes a candidate; a fine model's surface on a coarse lattice may have hundreds a vertex). More means
  // the surfaces moved many times their spacing in one step: the run stops like a blow-up instead of filling memory.
  int candidates_per_vertex = 128;
  long min_candidates = 8'000'000;
};

}  // namespace wobble::collision
