// The two collision primitives between triangle surfaces, as in Bridson, Fedkiw & Anderson 2002 ("Robust treatment
// of collisions, contact and friction for cloth animation", SIGGRAPH), section 6: a point against a triangle and an
// edge against an edge. Each pair is a stencil of four surface vertices (particles, or points blended from particles:
// contact/collisions/body_collisions.h) with weights w, so that the relative position (first element minus the nearest
// point of the second) is sum w_i x_i and the relative velocity sum w_i v_i. Distances are exact closest points
// (Ericson, "Real-Time Collision Detection", 5.1.5 and 5.1.9).
#pragma once
#include <array>

#include "sim/types.h"

namespace wobble::collision {

enum class Primitive { PointTriangle, EdgeEdge };

struct Stencil {
  std::array<int, 4> vertex;  // point-triangle: p, a, b, c; edge-edge: a0, a1, b0, b1
  std::array<double, 4> w;    // point-triangle: 1, -u, -v, -w; edge-edge: 1 - s, s, -(1 - t), -t
};

struct Closest {
  double distance;
  std::array<double, 4> w;  // as in Stencil
  Vec3 delta;               // sum w_i x_i: from the second element's nearest point to the first's
};

// The point of triangle abc nearest p, as barycentric weights.
Closest pointTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
// The nearest points of segments a0a1 and b0b1 (parallel segments: one of the nearest pairs).
Closest edgeEdge(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

}  // namespace wobble::collision
