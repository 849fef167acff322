// Contacts as velocity constraints, for implicit integrators: which particles a surface holds at a state.
#pragma once
#include "sim/contact.h"
#include "sim/dynamics.h"

namespace wobble {

// Replaces out by the particles whose support force addContactForces makes active at (t, x): within epsilon of a
// surface, with the smooth force f (everything but contact), relative to the surface's acceleration, pushing into
// it (activeSupport, shared with addContactForces). The first such collider per particle; pinned ones are skipped.
void findContactConstraints(Colliders colliders, double t, const VecX& x, const VecX& f, const VecX& mass,
                            const VecX& inv_mass, std::vector<ContactConstraint>& out);

}  // namespace wobble
