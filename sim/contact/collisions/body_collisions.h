// Contact between bodies and within a body's own surface: the pass that runs after every step, for every integrator
// (Bridson, Fedkiw & Anderson 2002, "Robust treatment of collisions, contact and friction for cloth animation";
// Harmon, Vouga, Tamstorf & Grinspun 2008, "Robust treatment of simultaneous collisions"; Provot 1997 for rigid impact
// zones). Given the step's start x0 (free of intersections) and the integrator's candidate end x1, v1, the particles
// of every surface move along x0 + s h vbar, vbar = (x1 - x0) / h, s in [0, 1]. The pass changes vbar only:
//   1. repulsion: each point-triangle and edge-edge pair within the contact thickness at x0 gets an inelastic impulse
//      that stops its approach, a repulsion capped by a spring of the bodies' stiffness over the thickness left,
//      and Coulomb friction on its tangential relative velocity (Bridson 2002, 7.2);
//   2. collisions: continuous detection of every pair along the trajectories (ccd.h); each hit gets an impulse that
//      stops the approach (with at most a tenth of it back as separation), in a fixed order, iterated up to
//      ccd_iterations rounds, each testing only the pairs whose particles moved in the last one;
//   3. fail-safe: hits left after those rounds merge their particles into rigid impact zones (union-find) that move as
//      rigid bodies with their linear and angular momentum (a zone holding a pinned particle stands still), until a
//      round finds no hit or zone_iterations rounds pass: then the pass fails.
// Then x1 = x0 + h vbar and v1 += vbar - (x1 - x0) / h for the particles whose vbar changed; every other byte of x1 and
// v1 is left as it was, so a step in which no two surfaces come within the thickness is unchanged. A step that cannot
// bring two elements within it (the particles' displacement since the clearance was measured cannot close it:
// candidates/clearance.h) skips the pass altogether.
// For an explicit integrator (resolve's resting; its v1 is not vbar) stage 1 also stops each pair that reaches the
// thickness within the step where it reaches it, and then the approach stage 1's pairs keep in v1 (what their load
// added within the step) is stopped by impulses on v1 alone (Repulsion::settle; Guendelman, Bridson & Fedkiw 2003:
// contact on the velocity after its update).
// An implicit integrator that carries the contacts in its solve (backward Euler: nearPairs below, a penalty on each
// pair's gap with its Jacobian) skips stage 1: its step ends with the pairs at the thickness already, and impulses on
// the touching particles alone would compress the springs behind them (the energy gain of docs/body-contact.md). So
// does RK4, which carries the same pairs as a penalty layer in its stages (stage_penalty.h). Stages 2 and 3 stay the
// guarantee that no surface passes through another.
// A surface's vertices are particles, or for a mesh jelly points riding on its lattice (each the trilinear blend of
// its cell's 8 particles, contact/colliders/weighted_points.h): such a vertex moves along the blend of its particles'
// straight trajectories, itself straight, so detection is the same on it; an impulse on a pair is handed to the
// particles of its vertices by the combined weights (up to 32 particles, each once) and their inverse masses, which
// gives the pair exactly the velocity change asked for (embedded collision proxies: Sifakis, Shinar, Irving & Fedkiw
// 2007; McAdams et al. 2011); impact zones gather the particles under the colliding vertices, and a rigid motion of the
// particles moves the points blended from them rigidly too.
#pragma once
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/contact/params.h"
#include "sim/contact/stats.h"
#include "sim/contact/surface_nodes.h"
#include "sim/dynamics.h"
#include "sim/types.h"

namespace wobble {

namespace collision {

// How BodyCollisions::resolve runs one step's pass.
struct PassOptions {
  // Stage 1's impulses (false where the integrator carried the contacts in its solve or stages; the pairs are still
  // counted).
  bool repulsion = true;
  // x0 is the same bytes as the x1 the last call left (the step before, taken on from where the pass left it;
  // Clearance::covers).
  bool continues = false;
  // The pass alone holds bodies resting on each other (an explicit integrator, whose end velocity is not the
  // trajectory's): with repulsion, stage 1 also stops the pairs that reach the thickness within the step, and the
  // approach the end velocities keep is stopped after (Repulsion::settle).
  bool resting = false;
};

class BodyCollisions {
 public:
  BodyCollisions(const std::vector<Surface>& surfaces, const VecX& inverse_mass, Settings settings, bool parallel);
  ~BodyCollisions();
  // Whether any pair of elements may collide at all: two bodies, or one with self-contact.
  static bool needed(const std::vector<Surface>& surfaces);
  // The pass over one step of size h from x0 to (x1, v1); see above and PassOptions. Nothing when the end is free of
  // collisions.
  std::optional<Failure> resolve(const VecX& x0, VecX& x1, VecX& v1, double h, PassOptions options = {});
  // For an implicit solve (ForceJacobian::bodyContacts): appends to out the pairs of elements, not in out yet, whose
  // gap, linearized at x0 along their nearest points' direction there, ends below 0 at x1 (candidates from the swept
  // boxes of x0 to x1; those of the step's first call, padded by half the thickness more, serve its later calls and
  // the pass while x0 is the same and every end lies within that margin of the first's). In a fixed order; returns
  // whether out grew. join: which of them it hands over (PairJoin; every one when left out), and how many it held back.
  bool nearPairs(const VecX& x0, const VecX& x1, std::vector<ContactPair>& out, PairJoin& join);
  bool nearPairs(const VecX& x0, const VecX& x1, std::vector<ContactPair>& out) {
    PairJoin every;
    return nearPairs(x0, x1, out, every);
  }
  const Stats& stats() const { return stats_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Stats stats_;
};

// Whether the broad phase takes its shortcuts (on by default): dropping the pairs a fixed axis keeps apart all
// through the step and those whose boxes meet but a diagonal keeps apart (an 18-DOP), in the later rounds of a step
// listing only the pairs with a particle that moved, and keeping a step's candidates and their nearest points at the
// start through an implicit step's solves and the pass after it (found once with a margin; see nearPairs). The pass
// finds the same contacts in the same order either way, only slower without; tests compare the two.
void setBroadPhaseCulls(bool on);

// Whether a step that cannot bring two surface elements within the thickness skips detection, the pass and backward
// Euler's searches (on by default; candidates/clearance.h: while the particles' displacement since the clearance was
// measured cannot close it). Off, every step runs them: the same bytes, slower where nothing is near; tests compare
// the two.
void setSkipWhileApart(bool on);

}  // namespace collision
}  // namespace wobble
