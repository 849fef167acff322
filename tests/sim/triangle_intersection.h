// An independent triangle-triangle intersection test for the contact tests (Moller 1997, "A fast triangle-triangle
// intersection test", journal of graphics tools 2(2)): written here from the paper, sharing nothing with the solver's
// proximity or continuous queries (sim/contact/), so that it can catch their mistakes. Touching counts as
// intersecting; no epsilon.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sim/surface.h"
#include "sim/types.h"

namespace wobble::testing {

namespace moller {

// The interval of the line L = O + t D cut by a triangle whose vertices project to p[k] on D and lie at signed
// distances d[k] from the other triangle's plane (no two on one side at 0, not all 0).
inline std::array<double, 2> interval(const std::array<double, 3>& p, const std::array<double, 3>& d) {
  // The vertex alone on its side (or at 0 while the other two share a side) is the apex.
  int apex;
  if (d[0] * d[1] > 0) apex = 2;
  else if (d[0] * d[2] > 0) apex = 1;
  else if (d[1] * d[2] > 0 || d[0] != 0) apex = 0;
  else if (d[1] != 0) apex = 1;
  else apex = 2;
  const int a = (apex + 1) % 3, b = (apex + 2) % 3;
  const double ta = p[apex] + (p[a] - p[apex]) * d[apex] / (d[apex] - d[a]);
  const double tb = p[apex] + (p[b] - p[apex]) * d[apex] / (d[apex] - d[b]);
  return {std::min(ta, tb), std::max(ta, tb)};
}

inline bool segmentsCross2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                            const Eigen::Vector2d& d) {
  const auto orient = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
    const double v = (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
    return (v > 0) - (v < 0);
  };
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 * o2 <= 0 && o3 * o4 <= 0) {
    if (o1 == 0 && o2 == 0) {  // collinear: overlapping projections on both axes
      return std::max(std::min(a.x(), b.x()), std::min(c.x(), d.x())) <=
                 std::min(std::max(a.x(), b.x()), std::max(c.x(), d.x())) &&
             std::max(std::min(a.y(), b.y()), std::min(c.y(), d.y())) <=
                 std::min(std::max(a.y(), b.y()), std::max(c.y(), d.y()));
    }
    return true;
  }
  return false;
}

inline bool inside2d(const Eigen::Vector2d& p, const std::array<Eigen::Vector2d, 3>& t) {
  double s[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d e = t[(k + 1) % 3] - t[k], q = p - t[k];
    s[k] = e.x() * q.y() - e.y() * q.x();
  }
  return (s[0] >= 0 && s[1] >= 0 && s[2] >= 0) || (s[0] <= 0 && s[1] <= 0 && s[2] <= 0);
}

// Both triangles in one plane of normal n: project on the axis plane where n is largest and test in 2D.
inline bool coplanar(const Vec3& n, const std::array<Vec3, 3>& v, const std::array<Vec3, 3>& u) {
  int drop;
  n.cwiseAbs().maxCoeff(&drop);
  const int i = (drop + 1) % 3, j = (drop + 2) % 3;
  std::array<Eigen::Vector2d, 3> a, b;
  for (int k = 0; k < 3; ++k) {
    a[k] = {v[k][i], v[k][j]};
    b[k] = {u[k][i], u[k][j]};
  }
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l)
      if (segmentsCross2d(a[k], a[(k + 1) % 3], b[l], b[(l + 1) % 3])) return true;
  return inside2d(a[0], b) || inside2d(b[0], a);
}

}  // namespace moller

inline bool trianglesIntersect(const std::array<Vec3, 3>& v, const std::array<Vec3, 3>& u) {
  // Signed distances within rounding of a plane are 0 (Moller's epsilon test): two triangles of one flat face of a
  // rotated jelly are coplanar, and the sign of rounding noise must not decide that they cross.
  double size = 0;
  for (int k = 0; k < 3; ++k) size = std::max({size, (v[k] - v[0]).norm(), (u[k] - v[0]).norm()});
  const auto snap = [&](std::array<double, 3>& d, const Vec3& n) {
    for (double& x : d)
      if (std::abs(x) <= 1e-12 * n.norm() * size) x = 0;
  };
  const Vec3 n1 = (v[1] - v[0]).cross(v[2] - v[0]);
  std::array<double, 3> du;
  for (int k = 0; k < 3; ++k) du[k] = n1.dot(u[k] - v[0]);
  snap(du, n1);
  if ((du[0] > 0 && du[1] > 0 && du[2] > 0) || (du[0] < 0 && du[1] < 0 && du[2] < 0)) return false;
  const Vec3 n2 = (u[1] - u[0]).cross(u[2] - u[0]);
  std::array<double, 3> dv;
  for (int k = 0; k < 3; ++k) dv[k] = n2.dot(v[k] - u[0]);
  snap(dv, n2);
  if ((dv[0] > 0 && dv[1] > 0 && dv[2] > 0) || (dv[0] < 0 && dv[1] < 0 && dv[2] < 0)) return false;
  const Vec3 d = n1.cross(n2);
  // Coplanar, or so nearly (planes within 1e-9 rad and within 1e-9 of the size of each other) that the line where the
  // planes meet is lost in rounding: decided in the plane, as Moller does for the coplanar case.
  const bool flat = d.norm() <= 1e-9 * n1.norm() * n2.norm() &&
                    std::max({std::abs(du[0]), std::abs(du[1]), std::abs(du[2])}) <= 1e-9 * n1.norm() * size;
  if ((du[0] == 0 && du[1] == 0 && du[2] == 0) || flat) return moller::coplanar(n1, v, u);
  int axis;
  d.cwiseAbs().maxCoeff(&axis);  // projecting on the largest axis of D orders points along L alike
  std::array<double, 3> pv, pu;
  for (int k = 0; k < 3; ++k) {
    pv[k] = v[k][axis];
    pu[k] = u[k][axis];
  }
  const auto a = moller::interval(pv, dv), b = moller::interval(pu, du);
  return a[0] <= b[1] && b[0] <= a[1];
}

// Bodies' surfaces as triangles of points (one entry per triangle), with their bodies. A point is a particle of the
// system, or for a mesh jelly's embedded surface the blend of its lattice cell's particles by the surface's own
// weights (SurfaceMesh::embedded: the positions that are rendered and written).
struct ParticleTriangles {
  std::vector<std::array<int, 3>> triangles;  // point indices
  std::vector<int> body;
  std::vector<std::vector<std::pair<int, double>>> points;  // each a sum of (particle, weight)
};

inline void addSurface(ParticleTriangles& out, const SurfaceMesh& mesh, int first, int body) {
  const int base = static_cast<int>(out.points.size());
  if (mesh.embedded.empty()) {
    int count = 0;  // points are the body's particles, by index
    for (const int p : mesh.particle) count = std::max(count, p + 1);
    for (int p = 0; p < count; ++p) out.points.push_back({{first + p, 1.0}});
  } else {
    for (const EmbeddedPoint& e : mesh.embedded) {
      out.points.emplace_back();
      for (int k = 0; k < 8; ++k) out.points.back().emplace_back(first + e.particle[k], e.weight[k]);
    }
  }
  // Surface vertices on one particle (or embedded point) share a point: adjacency is by position's source.
  for (const auto& t : mesh.triangles) {
    out.triangles.push_back({base + mesh.particle[t[0]], base + mesh.particle[t[1]], base + mesh.particle[t[2]]});
    out.body.push_back(body);
  }
}

// Intersecting pairs: any two triangles of different bodies, and two of one body that share no point. With list,
// also the pairs themselves (triangle indices), for messages.
inline int intersectingPairs(const ParticleTriangles& s, const VecX& x,
                             std::vector<std::array<int, 2>>* list = nullptr) {
  const int n = static_cast<int>(s.triangles.size());
  std::vector<Vec3> at(s.points.size());
  for (std::size_t p = 0; p < s.points.size(); ++p) {
    at[p] = Vec3::Zero();
    for (const auto& [q, w] : s.points[p]) at[p] += w * particle(x, q);
  }
  std::vector<std::array<Vec3, 3>> tri(n);
  std::vector<Vec3> lo(n), hi(n);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) tri[i][k] = at[s.triangles[i][k]];
    lo[i] = tri[i][0].cwiseMin(tri[i][1]).cwiseMin(tri[i][2]);
    hi[i] = tri[i][0].cwiseMax(tri[i][1]).cwiseMax(tri[i][2]);
  }
  // Sorted by the boxes' low x, each triangle is compared with those whose x ranges overlap its own.
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return lo[a].x() < lo[b].x(); });
  int count = 0;
  for (int oi = 0; oi < n; ++oi) {
    const int i = order[oi];
    for (int oj = oi + 1; oj < n && lo[order[oj]].x() <= hi[i].x(); ++oj) {
      const int j = order[oj];
      if ((lo[i].array() > hi[j].array()).any() || (lo[j].array() > hi[i].array()).any()) continue;
      if (s.body[i] == s.body[j]) {
        bool shared = false;
        for (int a : s.triangles[i])
          for (int b : s.triangles[j]) shared |= a == b;
        if (shared) continue;
      }
      if (!trianglesIntersect(tri[i], tri[j])) continue;
      ++count;
      if (list) list->push_back({i, j});
    }
  }
  return count;
}

}  // namespace wobble::testing
