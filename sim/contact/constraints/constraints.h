// Contacts as velocity constraints, for implicit integrators: which particles a surface holds at a state.
#pragma once
#include "sim/contact/colliders/response.h"
#include "sim/dynamics.h"

namespace wobble {

// Replaces out by the particles whose support force addContactForces makes active at (t, x, v): within epsilon of a
// surface, with the smooth force f (everything but contact), relative to the surface's acceleration, pushing into it
// (activeSupport, shared with addContactForces), and not moving away from it fast enough to leave the band within
// the step h. Every such collider's (a particle wedged between two surfaces has two constraints, a corner's particle
// three: Baraff & Witkin 1998, section 5.3), in particle order and, within a particle, collider order; pinned
// particles are skipped.
// released (when given): the particles whose support is active but which leave the band within the step, each with
// its support and friction force (supportForce with stick time 2 h): an implicit step takes that force out of its
// start force, since it cannot hold it for the whole step either (a stiff jelly's bottom layer, bounced off the
// floor, kept the support that cancelled its springs' push for a whole 1/60 s step: 14 J became 199 J in a step).
// Sized from the smooth force f, as the constraints are; addContactForces sizes a particle's second surface's support
// after its first's, so on a particle leaving two surfaces at once the second force taken out is approximate.
void findContactConstraints(Colliders colliders, double t, double h, const VecX& x, const VecX& v, const VecX& f,
                            const VecX& mass, const VecX& inv_mass, std::vector<ContactConstraint>& out,
                            std::vector<ReleasedSupport>* released = nullptr);

// Impacts inside an implicit step (Baraff & Witkin 1998, section 5: constraints enforced by the solve's filter). A
// candidate step from (x0, v0) at t to (x1, v1) at t + h that ends a particle below a surface constrains it along the
// surface's normal n at x1 to leave the step with the normal velocity
//   max(u1_n + e max(0, -(v0 - u0)_n),  v1_n - d1 / h):
// restitution's bounce on the approach speed at the step's start (u0, u1: the surface's velocity at t and t + h), or
// what lifts the end point onto the surface if that is more. Solved again with it, the springs carry the impulse to
// the rest of the body within the same step, and nothing is moved after the solve: a position projection after the
// step compresses the springs by the step's penetration without the solve's knowledge, and on a stiff jelly at a
// large step stored more energy than the body ever had (docs/energy.md). Every collider the step ends a particle
// below constrains it (impact set true), together with the impacts earlier calls found for it; its resting contacts
// (findContactConstraints) go, the same surface's as another's; pinned particles are skipped. out stays in particle
// order, collider order within a particle. Returns whether out changed.
bool addImpactConstraints(Colliders colliders, double t, double h, const VecX& x0, const VecX& v0, const VecX& x1,
                          const VecX& v1, const VecX& inv_mass, std::vector<ContactConstraint>& out);

}  // namespace wobble
