// Cheap proofs that two surface elements stay apart over a step, for the stages that would otherwise test them
// exactly: along a fixed direction each node's projection is linear in the step's fraction, so the gap between two
// elements' projections (the least of one's minus the greatest of the other's) is concave along the step, at least
// its smaller value at the step's ends, and the distance is at least that gap.
#pragma once
#include <algorithm>
#include <array>
#include <limits>

#include "sim/contact/distance/primitives.h"
#include "sim/types.h"

namespace wobble::collision {

// Collisions are reported within this fraction of the pair's thickness (ccd.h's eta): the cubic's roots are exact to
// rounding, so this only has to cover a touching root and the rounding of the closest-point query.
inline constexpr double kEtaFraction = 1e-3;

// The interval of a projection y(node) over count nodes.
struct Extent {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
};
template <class Project>
Extent extent(const int* nodes, int count, Project&& y) {
  Extent e;
  for (int i = 0; i < count; ++i) {
    const double v = y(nodes[i]);
    e.lo = std::min(e.lo, v), e.hi = std::max(e.hi, v);
  }
  return e;
}

// The gap between the elements q[0, first) and q[first, 4) of a pair along unit d (from the second to the first), at
// the nodes' positions x: the least projection of the first's nodes minus the greatest of the second's. Along a fixed
// d it is concave over a linear step, so at least its smaller value at the step's ends, and the distance is at least
// it.
inline double gapAlong(const Vec3& d, const VecX& x, const std::array<int, 4>& q, int first) {
  const auto along_d = [&](int node) { return d.dot(particle(x, node)); };
  return extent(q.data(), first, along_d).lo - extent(q.data() + first, 4 - first, along_d).hi;
}

// Whether the elements a (na nodes) and b (nb nodes), moving from x0 to x1, are further apart than gap all through
// the step, by a fixed axis that separates them by more than gap at both ends. The axes are x, y and z: the swept boxes
// overlap when the elements move together (a falling cloth), their boxes at each end mostly do not.
inline bool apartAllStep(const VecX& x0, const VecX& x1, const int* a, int na, const int* b, int nb, double gap) {
  for (int k = 0; k < 3; ++k) {
    bool ab = true, ba = true;  // a below b all along, b below a all along
    for (const VecX* x : {&x0, &x1}) {
      const auto along_axis = [&](int node) { return (*x)[3 * node + k]; };
      const Extent ea = extent(a, na, along_axis), eb = extent(b, nb, along_axis);
      ab = ab && eb.lo - ea.hi > gap;
      ba = ba && ea.lo - eb.hi > gap;
    }
    if (ab || ba) return true;
  }
  return false;
}

// Whether the elements (nodes q[0, first) and q[first, 4)), moving from x0 to x1, stay further apart than twice eta all
// through the step along the direction of their nearest points at the start, c (known: a distance that is not NaN):
// the fixed axis of apartAllStep, chosen to separate them most at the start. Spares the continuous test most pairs
// that move together (an explicit integrator's small steps).
inline bool apartAlongNearest(const VecX& x0, const VecX& x1, const Closest& c, const std::array<int, 4>& q, int first,
                              double thickness) {
  if (!(c.distance > 0)) return false;
  const Vec3 d = c.delta / c.distance;
  const double eta2 = 2 * kEtaFraction * thickness;
  for (const VecX* x : {&x0, &x1})
    if (!(gapAlong(d, *x, q, first) > eta2)) return false;
  return true;
}

}  // namespace wobble::collision
