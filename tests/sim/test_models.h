// Closed triangle models made in code for mesh-jelly tests and benchmarks.
#pragma once
#include <cmath>

#include "sim/bodies/model_mesh.h"

namespace wobble::testing {

// A UV sphere of radius r: rings x segments, poles as single points, counter-clockwise seen from outside.
inline ModelMesh uvSphere(double r, int rings, int segments) {
  ModelMesh m;
  m.points.emplace_back(0, r, 0);
  for (int k = 1; k < rings; ++k)
    for (int i = 0; i < segments; ++i) {
      const double th = EIGEN_PI * k / rings, ph = 2 * EIGEN_PI * i / segments;
      m.points.emplace_back(r * std::sin(th) * std::cos(ph), r * std::cos(th), -r * std::sin(th) * std::sin(ph));
    }
  m.points.emplace_back(0, -r, 0);
  const int south = int(m.points.size()) - 1;
  const auto at = [&](int k, int i) { return 1 + (k - 1) * segments + (i % segments); };
  for (int i = 0; i < segments; ++i) m.triangles.push_back({0, at(1, i), at(1, i + 1)});
  for (int k = 1; k + 1 < rings; ++k)
    for (int i = 0; i < segments; ++i) {
      m.triangles.push_back({at(k, i), at(k + 1, i), at(k + 1, i + 1)});
      m.triangles.push_back({at(k, i), at(k + 1, i + 1), at(k, i + 1)});
    }
  for (int i = 0; i < segments; ++i) m.triangles.push_back({south, at(rings - 1, i + 1), at(rings - 1, i)});
  return m;
}

// A box with one corner at the origin and the opposite one at size, 8 vertices, each face two triangles.
inline ModelMesh box(const Vec3& size) {
  ModelMesh m;
  for (int c = 0; c < 8; ++c) m.points.emplace_back(size.x() * (c & 1), size.y() * (c >> 1 & 1), size.z() * (c >> 2));
  // Each face as two triangles, outward: (-x, +x, -y, +y, -z, +z).
  m.triangles = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
  return m;
}

}  // namespace wobble::testing
