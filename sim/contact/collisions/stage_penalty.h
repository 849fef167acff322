// Contact between bodies inside an explicit integrator's stages (RK4's): a penalty layer, as Harmon, Vouga, Smith,
// Tamstorf & Grinspun 2009 ("Asynchronous contact mechanics") carry contact by penalty layers inside an explicit
// integrator, here one layer, of the contact thickness, with the pass after the step as the guarantee. The pairs within
// reach over the step (BodyCollisions::nearPairs from the step's start x0 towards x0 + h v0: each pair's gap
// g(x) = n . sum w_i x_i - thickness, linear in x, its normal and weights from x0) each get, while pressed (g < 0), a
// Kelvin-Voigt contact of the bodies' own material:
//   - a spring k on the thickness left, f_n = -k g along n: the potential k min(0, g)^2 / 2, conservative and C1 at
//     g = 0, so a pair joining or leaving the list adds no energy;
//   - a damper c on the relative normal velocity, critical for the pair's own mode (c = 2 sqrt(k m), m the pair's
//     effective mass), never pulling: a landing does not bounce off the layer;
//   - static friction: a tangential spring of the same k on the pair's tangential displacement since it stuck, carried
//     from step to step by its elements, with the damper c, at most mu f_n (Coulomb): past that the anchor slides.
// k is the two bodies' layers of the thickness in series, each of its springs' mean ks times rest length over the
// thickness (a bar of the material that long). The layer shares a particle's stability budget among the pairs on it
// (a pair's share of a particle is its w^2 over the particle's sum of w^2 over the step's pairs): a particle gains at
// most h^2 k / m = kMaxStiffness and h c / m = kMaxDamping however many pairs it is in. The stored energy (springs,
// friction's stretch) is part of the total energy the run's check sees (Simulation::heldEnergy). docs/body-contact.md.
#pragma once
#include <array>
#include <vector>

#include "sim/dynamics.h"
#include "sim/types.h"

namespace wobble::collision {

class StagePenalty {
 public:
  // The most a particle gains, over its mass: h^2 k / m and h c / m. The relative mode of two touching particles (half
  // their mass) then has an h omega of sqrt(2) on its own; with a soft jelly's stiffest mode at 2.4 (ks 100, 0.05 kg,
  // RK4 at 1/60 s) together 2.8, RK4's limit.
  static constexpr double kMaxStiffness = 1, kMaxDamping = 1;

  // Per particle: its body's springs' mean ks times rest length (N).
  explicit StagePenalty(std::vector<double> stiffness);

  // This step's pairs (taken from pairs), found from the step's start x0, with their terms for a step of h.
  void begin(std::vector<ContactPair>& pairs, const VecX& x0, const VecX& inverse_mass, double h);
  // After the step, at its end (x1, v1): each pressed pair's friction stretch, kept for the next step.
  void end(const VecX& x1, const VecX& v1);
  bool empty() const { return pairs_.empty(); }
  std::size_t size() const { return pairs_.size(); }
  // a += the pressed pairs' forces at (x, v) over the particles' masses.
  void addAccelerations(const VecX& x, const VecX& v, const VecX& inverse_mass, VecX& a) const;
  // The energy the pressed pairs' springs hold at x (J): normal and friction.
  double energy(const VecX& x) const;

 private:
  struct Term {
    double stiffness, damping;
    Vec3 r0;       // the pair's relative position at the step's start
    Vec3 stretch;  // its friction spring's stretch at the step's start (tangential)
  };
  struct Stuck {
    std::array<int, 4> element;  // ContactPair::element
    Vec3 stretch;
    bool operator<(const Stuck& o) const { return element < o.element; }
  };
  // Pair k's force on its relative position at (x, v), 0 unless pressed; with stretch, its friction's stretch there.
  Vec3 force(std::size_t k, const VecX& x, const VecX& v, Vec3* stretch = nullptr) const;
  // Pair k's gap and friction stretch at x.
  double gap(std::size_t k, const VecX& x, Vec3& stretch) const;

  std::vector<double> stiffness_;
  std::vector<ContactPair> pairs_;
  std::vector<Term> terms_;
  std::vector<Stuck> stuck_;   // the last step's pressed pairs, sorted
  std::vector<double> share_;  // per particle: sum of w^2 over the step's pairs (0 between steps)
};

}  // namespace wobble::collision
