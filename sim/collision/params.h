// What a scene sets for contact between bodies (sim/collision/body_collisions.h): per body, and the [contact] caps.
#pragma once

namespace wobble::collision {

// Per body, read from its scene table (scenes/README.md).
struct SurfaceParams {
  double thickness = 0.02;  // m: surfaces are kept this far apart (the larger of two bodies' values between them)
  double friction = 0.3;    // Coulomb coefficient (the mean of two bodies' values between them)
  bool self_contact = false;
};

// The caps of the [contact] table of a scene.
struct Settings {
  int ccd_iterations = 8;    // rounds of collision impulses before impact zones
  int zone_iterations = 64;  // rounds of impact zones before the pass gives up
  // Not a scene key: the most candidate pairs per surface vertex a step's broad phase may list (about 40 where a
  // cloth lies in four layers on itself); more means the surfaces moved many times their spacing in one step, and the
  // run stops like a blow-up instead of filling memory (about 120 bytes a candidate).
  int candidates_per_vertex = 128;
};

}  // namespace wobble::collision
