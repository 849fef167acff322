// Backward Euler's contact: the resting contacts' friction in the solve, and the further solves after the first while
// the solved step ends a particle inside a surface or changes which contact pairs are pressed (backward_euler.h).
#include <algorithm>

#include "sim/contact/constraints/filter.h"
#include "sim/integrators/backward_euler.h"

namespace wobble {

// Kinetic friction of the contacts sliding at the step's start (ContactConstraint::damping): the damper
// F_p = -c P (v_p - u1), P = I - n n^T, its Jacobian h c P in the matrix (exact over the step, positive
// semidefinite: it only takes energy out), its start force in the right-hand side. Baraff & Witkin (1998) hold
// contacts by the filter and leave friction explicit; an explicit friction sized from the start's forces and held for
// a 1/60 s step while the springs relax pushed a landing cloth sideways and stretched it (docs/contact.md). The
// matrix takes h c P as h c on the particle's own weight (self: one number a particle): the filter removes the
// normal n from the solve (S = I - n n^T, or on two surfaces the line both leave free), where P and I agree, and
// the prescribed normal change z along n meets S (h c z) = 0 either way. Sets sliding_ and adds the forces at v to
// rhs_ and the weights to the matrix.
void BackwardEuler::frictionBlocks(double h, const VecX& v) {
  sliding_.clear();
  for (const ContactConstraint& c : contacts_) {
    if (c.stick || !(c.damping > 0)) continue;
    sliding_.push_back({c, true});
    particle(rhs_, c.particle) -= (h * c.damping) * tangentialSlide(c, h, v);
  }
  addFrictionWeights(h);
}

void BackwardEuler::addFrictionWeights(double h) {
  for (const SlidingContact& s : sliding_)
    if (s.in_matrix) matrix_.self()[s.contact.particle] += h * s.contact.damping;
}

// After the filter is rebuilt for impacts: a sliding contact whose normal it no longer removes (its constraint gone
// with an impact, contact/constraints/constraints.h) leaves the matrix, where h c would damp its normal velocity too;
// its friction stays the start's force in the right-hand side (at most Coulomb's).
void BackwardEuler::dropFreedFriction(double h) {
  for (SlidingContact& s : sliding_)
    if (s.in_matrix && filter_.apply(s.contact.particle, s.contact.normal).squaredNorm() > 1e-12) {
      matrix_.self()[s.contact.particle] -= h * s.contact.damping;
      s.in_matrix = false;
    }
}

Vec3 BackwardEuler::tangentialSlide(const ContactConstraint& c, double h, const VecX& v) {
  const Vec3 u = particle(v, c.particle) - (c.surface_velocity + h * c.surface_acceleration);
  return u - c.normal.dot(u) * c.normal;
}

// Impacts (contact/constraints/constraints.h): while the solved step ends a particle inside a surface, constrain it
// along the normal to its bounce and solve again (warm-started), so the springs share its impulse with the body within
// the step; likewise while it ends two bodies' surface elements within their thickness (ForceJacobian::bodyContacts:
// the pairs' penalty, addPairs). At most kImpactPasses more solves (what still ends inside is lifted by the step
// end's projection, what still ends too near is the post-step pass's). Between bodies, a check that changes the
// activity of fewer than kSettledShare of the step's pairs (new pressed pairs included) and finds no impact ends the
// step with the last solve, the first check included (docs/body-contact.md, "Cost"): on a landing cloth the checks
// past the first few flipped tens of pairs among tens of thousands, and on a cloth lying collapsed on itself the
// first check a few tens among 95 000, each at the price of a solve; what they leave is the post-step pass's.
void BackwardEuler::solveImpacts(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v,
                                 double absolute) {
  for (int pass = 0; pass < (pairs_.empty() ? kImpactPasses : kBodyPasses); ++pass) {
    setEnd(h, x, v);
    const bool impacts = jacobian.impactConstraints(t, h, x, v, end_x_, end_v_, contacts_);
    bool settled = true;
    const std::size_t changes = pressPairs(jacobian, t, h, x, v, settled);
    if (!impacts && (changes == 0 || settled)) return;
    const bool pairs = changes > 0;
    error_.history = 0;  // this step's dv carries impulses: not the smooth error's measure
    if (impacts) {
      ++stats_.impact_solves;
      filter_.reset(jacobian.inverseMass());  // afresh: an impact replaces a resting contact's constraint
      constrainFilter(contacts_, filter_);
      dropFreedFriction(h);
      for (const ContactConstraint& c : contacts_)
        particle(dv_, c.particle) = filter_.apply(c.particle, particle(dv_, c.particle));
      addPrescribedChange(contacts_, filter_, h, dv_);
    }
    if (pairs) {
      ++stats_.body_contact_solves;
      ++stats_.body_contact_active_set_solves;
      applyPairs(h, x, v);
    }
    solve(rhs_, dv_, absolute);
  }
}

std::size_t BackwardEuler::pressPairs(const ForceJacobian& jacobian, double t, double h, const VecX& x, const VecX& v,
                                      bool& settled) {
  const bool found = jacobian.colliderPairs(t, h, x, v, end_x_, pairs_.list());
  PairJoin pressed = PenaltyPairs::pressed();
  const std::size_t changes =
      ((options_.body_contact_in_solve && jacobian.bodyContacts(x, end_x_, pairs_.list(), pressed)) || found ||
       !pairs_.empty())
          ? updatePairs(jacobian, h, x, end_x_, false)
          : 0;
  // Of the pairs within reach, handed over or not (the solve's are a few of them: PairJoin).
  settled = double(changes) < kSettledShare * double(pairs_.size() + pressed.held_back);
  return changes;
}

std::size_t BackwardEuler::updatePairs(const ForceJacobian& jacobian, double h, const VecX& x0, const VecX& x1,
                                       bool first) {
  return pairs_.update(jacobian.inverseMass(), h, x0, x1, first, parallel_);
}

void BackwardEuler::applyPairs(double h, const VecX& x, const VecX& v) {
  error_.history = 0;  // this step's dv carries contact: not the smooth error's measure
  stats_.body_contact_pairs += pairs_.apply(h, x, v, matrix_, rhs_);
}

}  // namespace wobble
