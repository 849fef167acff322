#include "sim/bodies/model_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace wobble {
namespace {

std::string position(const Vec3& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

}  // namespace

Eigen::Matrix3d Placement::rotation() const {
  if (rotation_deg == 0 || rotation_axis.norm() == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(rotation_deg * EIGEN_PI / 180, rotation_axis.normalized()).toRotationMatrix();
}

std::string checkModel(const ModelMesh& mesh, bool closed) {
  if (mesh.points.empty() || mesh.triangles.empty()) return "the mesh is empty (no triangles)";
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (!mesh.points[i].allFinite())
      return "vertex " + std::to_string(i + 1) + " has a coordinate that is not finite (NaN or infinite)";
  const int n = static_cast<int>(mesh.points.size());
  double area = 0;
  // Each undirected edge with how many triangles use it.
  std::map<std::pair<int, int>, int> edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
      if (tri[k] < 0 || tri[k] >= n)
        return "triangle " + std::to_string(t + 1) + " names vertex " + std::to_string(tri[k] + 1) + " of " +
               std::to_string(n);
    const Vec3 &a = mesh.points[tri[0]], &b = mesh.points[tri[1]], &c = mesh.points[tri[2]];
    area += 0.5 * (b - a).cross(c - a).norm();
    for (int k = 0; k < 3; ++k) {
      const int u = tri[k], v = tri[(k + 1) % 3];
      ++edges[{std::min(u, v), std::max(u, v)}];
    }
  }
  if (!(area > 0)) return "the mesh is degenerate: its triangles have zero total area";
  std::int64_t boundary = 0;
  std::pair<int, int> first_boundary{-1, -1};
  for (const auto& [edge, count] : edges) {
    if (count > 2)
      return "the mesh is not manifold: the edge between vertices " + std::to_string(edge.first + 1) + " " +
             position(mesh.points[edge.first]) + " and " + std::to_string(edge.second + 1) + " " +
             position(mesh.points[edge.second]) + " has " + std::to_string(count) + " triangles (at most 2)";
    if (count == 1 && boundary++ == 0) first_boundary = edge;
  }
  if (!closed) return "";
  if (boundary > 0)
    return "the mesh is not closed: " + std::to_string(boundary) + " boundary edge" + (boundary > 1 ? "s" : "") +
           " (holes), one between vertices " + std::to_string(first_boundary.first + 1) + " " +
           position(mesh.points[first_boundary.first]) + " and " + std::to_string(first_boundary.second + 1) + " " +
           position(mesh.points[first_boundary.second]) + "; a jelly needs a closed (watertight) mesh";
  const double volume = meshVolume(mesh.points, mesh.triangles);
  Eigen::AlignedBox3d box;
  for (const Vec3& p : mesh.points) box.extend(p);
  if (!(std::abs(volume) > 1e-12 * box.diagonal().prod()) || !(std::abs(volume) > 0))
    return "the mesh is degenerate: it encloses zero volume";
  if (volume < 0) return "the mesh is inside out: its triangles wind clockwise seen from outside (negative volume)";
  return "";
}

std::vector<Vec3> localPoints(const ModelMesh& mesh, double scale) {
  Eigen::AlignedBox3d box;
  for (const Vec3& p : mesh.points) box.extend(p);
  const Vec3 mid = box.center();
  std::vector<Vec3> out;
  out.reserve(mesh.points.size());
  for (const Vec3& p : mesh.points) out.push_back(scale * (p - mid));
  return out;
}

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double meshVolume(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles) {
  double six_v = 0;
  for (const auto& t : triangles) six_v += points[t[0]].dot(points[t[1]].cross(points[t[2]]));
  return six_v / 6;
}

}  // namespace wobble
