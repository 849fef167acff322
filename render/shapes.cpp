// Quad and box triangulations with outward normals and per-face UVs (see shapes.h).
#include "render/shapes.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

namespace wobble::render {

using Eigen::Vector2f;
using Eigen::Vector3f;

TriangleMesh quadMesh(const std::string& name, const Quad& q) {
  if (!q.center.allFinite() || !q.normal.allFinite() || q.normal.norm() == 0 || !(q.size > 0) ||
      !std::isfinite(q.size) || !(q.uv_repeat > 0))
    throw std::invalid_argument("quad '" + name + "': needs a finite centre, a non-zero normal and positive size");
  const Vector3f n = q.normal.normalized();
  Vector3f u = n.cross(Vector3f::UnitZ());
  if (u.norm() < 1e-3f) u = n.cross(Vector3f::UnitY());
  u.normalize();
  const Vector3f v = n.cross(u);
  const float h = 0.5f * q.size;
  TriangleMesh m;
  m.name = name;
  m.positions = {q.center - h * u - h * v, q.center + h * u - h * v, q.center + h * u + h * v,
                 q.center - h * u + h * v};
  m.normals.assign(4, n);
  const float r = q.uv_repeat;
  m.uv = {Vector2f(0, 0), Vector2f(r, 0), Vector2f(r, r), Vector2f(0, r)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};  // u x v = n: counter-clockwise seen from the normal's side
  return m;
}

TriangleMesh boxMesh(const std::string& name, const Box& b) {
  if (!b.center.allFinite() || !b.size.allFinite() || !(b.size.minCoeff() > 0))
    throw std::invalid_argument("box '" + name + "': needs a finite centre and positive size");
  TriangleMesh m;
  m.name = name;
  const Vector3f h = 0.5f * b.size;
  // One face per axis and sign: outward normal n, and in-face axes u, v with u x v = n.
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {1.0f, -1.0f}) {
      const Vector3f n = sign * Vector3f::Unit(axis);
      const Vector3f u = sign * Vector3f::Unit((axis + 1) % 3);
      const Vector3f v = Vector3f::Unit((axis + 2) % 3);
      const int base = static_cast<int>(m.positions.size());
      const Vector3f c = b.center + n.cwiseProduct(h);
      const Vector3f du = u.cwiseProduct(h), dv = v.cwiseProduct(h);
      m.positions.insert(m.positions.end(), {c - du - dv, c + du - dv, c + du + dv, c - du + dv});
      m.normals.insert(m.normals.end(), 4, n);
      m.uv.insert(m.uv.end(), {Vector2f(0, 0), Vector2f(1, 0), Vector2f(1, 1), Vector2f(0, 1)});
      m.triangles.push_back({base, base + 1, base + 2});
      m.triangles.push_back({base, base + 2, base + 3});
    }
  return m;
}

void checkSphere(const std::string& name, const Sphere& s) {
  if (!s.center.allFinite() || !(s.radius > 0) || !std::isfinite(s.radius))
    throw std::invalid_argument("sphere '" + name + "': needs a finite centre and a positive radius");
}

}  // namespace wobble::render
