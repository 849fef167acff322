// The contact pairs of a backward-Euler step (ContactPair: two bodies' surface elements, or an embedded surface's point
// against a collider) and their penalty inside the solve. Each pair, with gap g(x) = n . sum w_i x_i - thickness linear
// in x over the step, has the one-sided penalty energy k min(0, g - g_rest)^2 / 2: convex, so backward Euler solved
// exactly with it never gains energy (docs/body-contact.md). The force at the step's end F_i = -k (g(x1) - g_rest) w_i
// n while the pair is pressed (active), its Jacobian -k w_i w_j n n^T: exact over the step, the system gains h^2 k u
// u^T (u: the w_i n) as a stencil block, the right-hand side h (F(x0) + h dF/dx v0) = -h k (g(x0) - g_rest + h n . sum
// w_i v0_i) w_i n. Which pairs are pressed is found by solving: active while the solved end has g(x1) < g_rest (an
// active set, from the last step's and updated after each solve; a pair pulled would be an attraction the one-sided
// energy does not have, and a source of energy: only within kActiveSlack of the rest gap does a pair keep its activity
// against the solved end). The stiffness k = kPenalty m / h^2 (m = 1 / sum w_i^2 / m_i, the pair's effective mass).
// g_rest is 0, or for a pair already within the thickness all but kRecovery of its overlap (a tenth a step, as Bridson
// 2002's repulsion): a pair that entered the thickness outside the solve is not pushed out at once with the energy of
// its whole overlap. Coulomb friction between pressed pairs is a tangential damper lagged by a step (carry), as IPC
// lags its friction (Li et al. 2020, "Incremental Potential Contact"), kept within Coulomb's cone over the step as the
// colliders' friction is (Bridson, Fedkiw & Anderson 2002, section 7.2: BackwardEuler::boundFriction).
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "sim/dynamics.h"
#include "sim/solver/pair_block_matrix.h"

namespace wobble {

class PenaltyPairs {
 public:
  // The share of a pair's overlap of the thickness that its penalty removes in a step (update).
  static constexpr double kRecovery = 0.1;
  // The penalty's h^2 k over the pair's effective mass; measured in docs/body-contact.md.
  static constexpr double kPenalty = 100;
  // A pair whose solved end is within this share of its start distance (at most of the thickness: activeSlack) of its
  // penalty's rest gap keeps its activity: without it, the last solves of a step flip a few hundred pairs by a
  // fiftieth of the thickness each.
  static constexpr double kActiveSlack = 0.25;
  // m/s: below this sliding speed friction between bodies holds (carry), as on colliders.
  static constexpr double kStickSpeed = ContactConstraint::kStickSpeed;

  // Forgets the pairs the last step left pressed (a new topology: their particles' numbers are another's).
  void forget() {
    carried_.clear();
    pairs_.clear();
    terms_.clear();
  }
  // Starts a step with no pairs; returns the join of its first search: the pairs the last step left pressed.
  PairJoin begin();
  // The join of a search after a solve: the pairs its end presses past the active set's slack.
  static PairJoin pressed() { return {.pressed = true, .recovery = kRecovery, .slack = kActiveSlack}; }

  // This step's pairs, in the order found: the searches append to it.
  std::vector<ContactPair>& list() { return pairs_; }
  bool empty() const { return pairs_.empty(); }
  // Whether an active pair holds an embedded point against a collider (ContactPair::collider).
  bool pressesCollider() const {
    for (std::size_t k = 0; k < pairs_.size() && k < terms_.size(); ++k)
      if (pairs_[k].collider && terms_[k].active) return true;
    return false;
  }
  std::size_t size() const { return pairs_.size(); }

  // Sets the terms of the pairs found since the last call and each pair's activity at the solved end x1 (first: the
  // step's first pairs, active as the last step left them, with its friction); returns how many changed.
  std::size_t update(const VecX& inverse_mass, double h, const VecX& x0, const VecX& x1, bool first, bool parallel);
  // The right-hand side and stencils of the active pairs (with friction: their dampers, or Coulomb's forces in their
  // place), in place of what the step's last call added to rhs; returns how many pairs are active.
  long apply(double h, const VecX& x, const VecX& v, PairBlockMatrix& matrix, VecX& rhs);
  // Keeps the active pairs for the next step, each with its Coulomb friction at the step's end (x + h (v + dv), v +
  // dv).
  void carry(double h, const VecX& x, const VecX& v, const VecX& dv);
  // f += the active pairs' penalty and friction forces at (x1, v1) (Newton's residual).
  void addForces(const VecX& x1, const VecX& v1, VecX& f) const;

  // Coulomb's cone over the step (BackwardEuler::boundFriction, which bounds the colliders' friction the same way).
  // Whether an active pair has friction in the solve (a damper, or Coulomb's force in its place).
  bool hasFriction() const;
  // For each active pair whose damper acts: fn(k, impulse, bound), its friction impulse over the step at the solved end
  // (x1, v1), -h c P u1 on the pair's relative motion (u1 = sum w_i v1_i), and Coulomb's bound on it, mu h N1 (N1 its
  // penalty's force there).
  template <class Fn>
  void frictionImpulses(double h, const VecX& x1, const VecX& v1, Fn&& fn) const;
  const ContactPair& pair(std::size_t k) const { return pairs_[k]; }
  // Pair k's damper gives way to Coulomb's force (N, on its relative motion) for the rest of the step.
  void bound(std::size_t k, const Vec3& force) { terms_[k].damping = 0, terms_[k].coulomb = force; }
  // Coulomb's forces turned against the relative slip at v1 (they would do positive work) become dampers of the same
  // force at that slip, kept for the rest of the step; returns whether any did.
  bool dampTurned(const VecX& v1);
  // The active pairs' share of the incremental potential at (x1, v1): the penalty's energy k (g(x1) - g_rest)^2 / 2
  // and h times the friction's dissipation c |P u1|^2 / 2 (their forces' potential: addForces).
  double potential(double h, const VecX& x1, const VecX& v1) const;
  // The work the active pairs' penalty forces at the end x1 do over the step from x0 (the forces backward Euler's step
  // holds over it): -k (g(x1) - g_rest) (g(x1) - g(x0)) each, the pairs between bodies only (an embedded point's
  // against a collider is the collider's).
  double work(const VecX& x0, const VecX& x1) const;

 private:
  struct Term {
    double stiffness;             // N/m of the penalty (0: a pair of pinned particles)
    double damping;               // N s/m of friction (carried from the step before: carry)
    double rest;                  // m: the gap the penalty holds (update)
    double slack;                 // m: the band around rest in which the pair keeps its activity (activeSlack)
    bool active;                  // pressed at the last solved end
    Vec3 coulomb = Vec3::Zero();  // N: Coulomb's force in place of the damper (bound)
    bool turned = false;          // its damper is dampTurned's: not bounded again
  };
  struct Carried {
    std::array<int, 4> element;  // ContactPair::element
    double damping;
    bool operator<(const Carried& o) const { return element < o.element; }
  };
  // How many of the pairs 0 .. n - 1 fn(pair) returns true for, each pair once, on threads.
  template <class Fn>
  std::size_t countOverPairs(std::size_t n, bool parallel, Fn&& fn);

  std::vector<ContactPair> pairs_;                    // this step's, in the order found
  std::vector<Term> terms_;                           // the same order
  std::vector<Carried> carried_;                      // the last step's active pairs, sorted
  std::vector<std::array<int, 4>> carried_elements_;  // their elements (the step's first search: PairJoin::only)
  VecX rhs_pairs_;                        // what the last apply added to the right-hand side (taken off at the next)
  std::vector<std::size_t> pair_counts_;  // countOverPairs' per chunk
};

template <class Fn>
void PenaltyPairs::frictionImpulses(double h, const VecX& x1, const VecX& v1, Fn&& fn) const {
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    const Term& term = terms_[k];
    if (!term.active || !(term.damping > 0) || term.turned) continue;
    const ContactPair& c = pairs_[k];
    const Vec3 u = c.relative(v1);
    const Vec3 impulse = -h * term.damping * (u - c.normal.dot(u) * c.normal);
    fn(k, impulse, c.friction * h * term.stiffness * std::max(0.0, term.rest - c.gap(x1)));
  }
}

}  // namespace wobble
