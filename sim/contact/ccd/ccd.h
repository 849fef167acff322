// Continuous collision detection on linear trajectories over one step (Provot 1997, "Collision and self-collision
// handling in cloth model dedicated to design garments"; Bridson, Fedkiw & Anderson 2002, section 6.4): four points
// moving from x0 to x1 are coplanar where the cubic f(t) = (x1(t) - x0(t)) . ((x2(t) - x0(t)) x (x3(t) - x0(t)))
// vanishes. Its roots in [0, 1] are isolated robustly by splitting [0, 1] at the roots of f' (where f is monotone)
// and bisecting each interval with a sign change; f's extrema and t = 1 are candidates too, so that a touching
// (double) root is not missed. At each candidate, in time order, the primitive's distance is checked: the first
// within eta, with the elements approaching each other, is the collision.
#pragma once
#include <optional>
#include <vector>

#include "sim/contact/distance/primitives.h"

namespace wobble::collision {

// Coefficients c0 + c1 t + c2 t^2 + c3 t^3 of the coplanarity cubic of p = x1 - x0, b = x2 - x0, c = x3 - x0, given
// at t = 0 and their changes dp, db, dc over the step.
std::array<double, 4> coplanarityCubic(const Vec3& p, const Vec3& b, const Vec3& c, const Vec3& dp, const Vec3& db,
                                       const Vec3& dc);

// The candidate times in [0, 1], ascending: the cubic's roots (bisected to full precision), its extrema, and 1.
// Always includes every root in [0, 1] of the cubic (to within the bisection's precision).
void candidateTimes(const std::array<double, 4>& cubic, std::vector<double>& out);

struct Hit {
  double t;     // time of contact as a fraction of the step
  Closest at;   // closest points at t
  Vec3 normal;  // unit, oriented along the relative position at the step's start (from second to first)
};

// The first time in [0, 1] at which the four points of the stencil (order as in Stencil), moving linearly from x0
// to x1, are within eta and approaching. Nothing if none.
std::optional<Hit> firstHit(Primitive kind, const std::array<Vec3, 4>& x0, const std::array<Vec3, 4>& x1, double eta);

}  // namespace wobble::collision
