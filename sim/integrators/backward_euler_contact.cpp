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
  coulomb_.clear();
  for (const ContactConstraint& c : contacts_)
    if (!c.stick && c.damping > 0) addSliding(c, h, v);
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

namespace {

// A contact's friction may exceed Coulomb's bound by this share before the step is solved again within it: a sliding
// contact's lagged damper gives mu N (1 + a h / |v|) in a slide accelerating at a, within the share from |v| = 10 a h
// on, so a steady slide costs no further solve.
constexpr double kConeSlack = 0.1;
// At most this many further solves a step to bring the friction into the cone (what is left is the next step's).
constexpr int kFrictionPasses = 3;
// m/s: an excess over the cone is worth a further solve when taking it off would change the particle's velocity by at
// least this, its neighbours held (the excess impulse over the particle's diagonal of the matrix along it: its mass,
// h^2 its springs' stiffness and h its dampers), or a body's by this as one rigid body (its contacts' excesses summed
// over its free mass: a stiff body whose every contact pulls the same way, whatever other bodies rest elsewhere).
// ContactConstraint::kStickSpeed, the slip below which friction counts a contact as stuck.
constexpr double kMaterialSpeed = ContactConstraint::kStickSpeed;

}  // namespace

// Coulomb's cone over the step (Bridson, Fedkiw & Anderson 2002, section 7.2: the friction impulse at most mu times the
// normal impulse; Baraff & Witkin 1998, section 5: the constraint force is the residual's filtered-out part, A dv - b).
// The hold (a sticking contact, filtered out in every direction) takes whatever tangential impulse J_t the solve needs,
// and with the whole body's springs pulling on one particle that may be many times mu J_n (a stiff jelly on a slope
// stalls); a sliding contact's damper, sized at the start's slip (at least
// ContactConstraint::kStickSpeed), gives h c |s1| at the end's slip s1, as unbounded when a slow slip speeds up; so
// does a contact pair's damper between bodies (PenaltyPairs: sized on the last step's slip, its normal impulse h N1 its
// penalty's force at the solved end, its impulse spread on its stencil's particles by their weights).
// Any of them, over the cone by more than kConeSlack, gives way to Coulomb's impulse mu J_n against the pull (the
// hold's J_t) or the end's slip, a constant force in the right-hand side and in F0 (Newton's iteration keeps it), and
// the step is solved again (at most kFrictionPasses times). A constant force may overshoot where the solve turns the
// slip against it (its neighbours let go too): it would then do positive work, so such a contact takes a damper of the
// same force at that slip instead, F = -c (I - n n^T)(v1 - u1), which only takes energy out. J_n = J . n + h N: the
// constraint's normal impulse plus the support N in F0 (less the damper's h c on the prescribed normal change, which
// the matrix's h c I adds). A particle on several surfaces is left as it is (its normal impulses are not separable from
// the residual). The holds and dampers give way only where their excess is material (kMaterialSpeed): in a cloth
// lying on a floor most holds exceed the cone at every step, pulling against each other, and letting them slide would
// move them by microns for further solves.
bool BackwardEuler::boundFriction(const ForceJacobian& jacobian, double h, const VecX& x, const VecX& v,
                                  double absolute) {
  const bool holds = !sliding_.empty() || std::any_of(contacts_.begin(), contacts_.end(),
                                                      [](const ContactConstraint& c) { return c.stick; });
  if (!holds && !pairs_.hasFriction()) return false;  // no friction to bound
  bool solved = false;
  const VecX& inv_mass = jacobian.inverseMass();
  // Per body (ForceJacobian::bodyFirsts): its free particles' mass, summed when first needed.
  const std::vector<int>& firsts = jacobian.bodyFirsts();
  const auto bodyOf = [&](int p) {
    return int(std::upper_bound(firsts.begin(), firsts.end(), p) - firsts.begin()) - 1;
  };
  bool massed = false;  // body_mass_ summed
  for (int pass = 0; pass < kFrictionPasses; ++pass) {
    VecX& product = friction_product_;  // sized with the topology (step); the holds' and dampers' impulses only
    if (holds) matrix_.multiply(dv_, product, parallel_);
    setEnd(h, x, v);
    const auto coulomb = [&](const ContactConstraint& c, const Vec3& force) {
      particle(rhs_, c.particle) += h * force;
      particle(f0_, c.particle) += inv_mass[c.particle] * force;
      coulomb_.push_back({c, force});
    };
    bool changed = false;
    // Coulomb's force turned against the slip: a damper instead (it would do positive work: always).
    for (CoulombFriction& k : coulomb_) {
      if (k.damped) continue;
      const double damping = ContactConstraint::turnedDamping(k.force, tangentialSlide(k.contact, h, end_v_));
      if (damping == 0) continue;
      k.damped = changed = true;
      particle(rhs_, k.contact.particle) -= h * k.force;
      particle(f0_, k.contact.particle) -= inv_mass[k.contact.particle] * k.force;
      k.contact.damping = damping;
      addSliding(k.contact, h, v, true);
    }
    bool reapply = pairs_.dampTurned(end_v_);  // the pairs' likewise
    changed = changed || reapply;
    // The holds and dampers over the cone, each with Coulomb's force in its place and the excess impulse that
    // force takes off; whether the excess is material (kMaterialSpeed).
    excess_friction_.clear();
    bool material = false;
    // Per body: the friction impulses of its every hold and damper checked, and their cones' bounds.
    std::vector<Vec3>& net = body_net_;
    std::vector<double>& capacity = body_capacity_;
    net.assign(firsts.size(), Vec3::Zero());
    capacity.assign(firsts.size(), 0.0);
    // The velocity change that taking the excess off would make along it (its particles' neighbours held): the
    // excess over the particle's diagonal, or for a pair over its particles' diagonals by their weights.
    const auto excess = [&](int index, ExcessFriction::Kind kind, const Vec3& force, const Vec3& taken) {
      if (excess_friction_.empty()) matrix_.diagonal(diagonal_, parallel_);
      excess_friction_.push_back({index, kind, force});
      const Vec3 t = taken.normalized();
      double mobility = 0;  // m/s per N s along t
      if (kind == ExcessFriction::Pair) {
        const WeightedStencil& s = pairs_.pair(index).stencil;
        for (int i = 0; i < s.size; ++i)
          if (inv_mass[s.particle[i]] > 0) mobility += s.w[i] * s.w[i] / t.dot(diagonal_[s.particle[i]] * t);
      } else {
        const int p = kind == ExcessFriction::Hold ? contacts_[index].particle : sliding_[index].contact.particle;
        mobility = 1 / t.dot(diagonal_[p] * t);
      }
      material = material || taken.norm() * mobility >= kMaterialSpeed;
    };
    for (std::size_t i = 0; i < contacts_.size(); ++i) {
      const ContactConstraint& c = contacts_[i];
      const bool alone = (i == 0 || contacts_[i - 1].particle != c.particle) &&
                         (i + 1 == contacts_.size() || contacts_[i + 1].particle != c.particle);
      if (!c.stick || !alone) continue;
      const Vec3 j = particle(product, c.particle) - particle(rhs_, c.particle);
      const Vec3 jt = j - j.dot(c.normal) * c.normal;
      const double bound = c.mu * std::max(0.0, j.dot(c.normal) + h * c.support);
      const int b = bodyOf(c.particle);
      net[b] += jt, capacity[b] += bound;
      if (!(jt.norm() > (1 + kConeSlack) * bound)) continue;
      excess(int(i), ExcessFriction::Hold, (bound / h) * jt.normalized(), (jt.norm() - bound) * jt.normalized());
    }
    for (std::size_t i = 0; i < sliding_.size(); ++i) {
      const ContactConstraint& c = sliding_[i].contact;
      if (!sliding_[i].in_matrix || sliding_[i].bounded || filter_.kind(c.particle) != ParticleFilter::Normal) continue;
      const Vec3 j = particle(product, c.particle) - particle(rhs_, c.particle);
      const double bound =
          c.mu * std::max(0.0, (j - h * c.damping * particle(dv_, c.particle)).dot(c.normal) + h * c.support);
      const Vec3 slide = tangentialSlide(c, h, end_v_);
      const int b = bodyOf(c.particle);
      net[b] -= h * c.damping * slide, capacity[b] += bound;
      if (!(h * c.damping * slide.norm() > (1 + kConeSlack) * bound)) continue;
      excess(int(i), ExcessFriction::Damper, -(bound / h) * slide.normalized(),
             -(h * c.damping * slide.norm() - bound) * slide.normalized());
    }
    // A pair's impulse acts on its two sides' bodies, by its weights (sum w_i = 0: the two sides' shares opposite).
    pairs_.frictionImpulses(h, end_x_, end_v_, [&](std::size_t k, const Vec3& jt, double bound) {
      const WeightedStencil& s = pairs_.pair(k).stencil;
      for (int i = 0; i < s.size; ++i)
        if (inv_mass[s.particle[i]] > 0) {
          const int b = bodyOf(s.particle[i]);
          net[b] += s.w[i] * jt, capacity[b] += std::abs(s.w[i]) * bound;
        }
      if (!(jt.norm() > (1 + kConeSlack) * bound)) return;
      excess(int(k), ExcessFriction::Pair, (bound / h) * jt.normalized(), (jt.norm() - bound) * jt.normalized());
    });
    if (!excess_friction_.empty() && !material) {
      std::vector<double>& body_mass = body_mass_;
      if (!massed) {
        massed = true;
        body_mass.assign(firsts.size(), 0.0);
        for (Eigen::Index p = 0; p < inv_mass.size(); ++p)
          if (inv_mass[p] > 0) body_mass[bodyOf(int(p))] += jacobian.mass()[p];
      }
      for (std::size_t b = 0; b < firsts.size() && !material; ++b)
        material = body_mass[b] > 0 && net[b].norm() - capacity[b] >= kMaterialSpeed * body_mass[b];
    }
    bool refilter = false;
    if (material) {
      for (const ExcessFriction& o : excess_friction_) {
        if (o.kind == ExcessFriction::Pair) {  // the pair's damper gives way to Coulomb's force
          pairs_.bound(std::size_t(o.index), o.force);
          reapply = true;
        } else if (o.kind == ExcessFriction::Hold) {  // the hold lets the particle slide
          ContactConstraint& c = contacts_[o.index];
          c.stick = false;
          refilter = true;
          coulomb(c, o.force);
        } else {  // the damper gives way to Coulomb's force
          SlidingContact& s = sliding_[o.index];
          const ContactConstraint& c = s.contact;
          s.in_matrix = false;
          matrix_.self()[c.particle] -= h * c.damping;
          particle(rhs_, c.particle) += (h * c.damping) * tangentialSlide(c, h, v);
          coulomb(c, o.force);
        }
      }
      changed = true;
    }
    if (!changed) break;
    ++stats_.friction_solves;
    if (reapply) pairs_.apply(h, x, v, matrix_, rhs_);  // the pairs bounded or turned
    if (refilter) {
      filter_.reset(inv_mass);
      constrainFilter(contacts_, filter_);
      for (const ContactConstraint& c : contacts_)
        particle(dv_, c.particle) = filter_.apply(c.particle, particle(dv_, c.particle));
      addPrescribedChange(contacts_, filter_, h, dv_);
    }
    solve(rhs_, dv_, absolute);
    solved = true;
  }
  return solved;
}

void BackwardEuler::addSliding(const ContactConstraint& c, double h, const VecX& v, bool bounded) {
  sliding_.push_back({c, true, bounded});
  particle(rhs_, c.particle) -= (h * c.damping) * tangentialSlide(c, h, v);
  matrix_.self()[c.particle] += h * c.damping;
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
