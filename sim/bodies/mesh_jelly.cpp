#include "sim/bodies/mesh_jelly.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "sim/bodies/jelly.h"
#include "sim/bodies/lattice.h"

namespace wobble {
namespace {

// Cell coordinate of p along each axis, and the fraction within that cell, clamped into the lattice.
void locate(const LatticeFill& f, const Vec3& p, std::array<int, 3>& cell, Vec3& t) {
  for (int a = 0; a < 3; ++a) {
    const double s = (p[a] - f.origin[a]) / f.h;
    cell[a] = std::clamp(static_cast<int>(std::floor(s)), 0, f.cells[a] - 1);
    t[a] = std::clamp(s - cell[a], 0.0, 1.0);
  }
}

// The rows are nudged off the cell-centre lines by irrational fractions of a cell: a ray through the centre of a cube
// face would run along the diagonal that splits it into two triangles and count it twice or not at all.
constexpr double kRowNudgeY = 1e-7 * 0.41421356237309515, kRowNudgeZ = 1e-7 * 0.7320508075688772;

void markInside(LatticeFill& f, const std::vector<Vec3>& pts, const std::vector<std::array<int, 3>>& tris) {
  const int nx = f.cells[0], ny = f.cells[1], nz = f.cells[2];
  std::vector<std::vector<std::pair<double, int>>> rows(std::size_t(ny) * nz);  // (x of crossing, +1 in / -1 out)
  for (const auto& t : tris) {
    const Vec3 &a = pts[t[0]], &b = pts[t[1]], &c = pts[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    if (n.x() == 0) continue;  // parallel to the rays
    const double ylo = std::min({a.y(), b.y(), c.y()}), yhi = std::max({a.y(), b.y(), c.y()});
    const double zlo = std::min({a.z(), b.z(), c.z()}), zhi = std::max({a.z(), b.z(), c.z()});
    const int j0 = std::max(0, int(std::floor((ylo - f.origin.y()) / f.h - 0.5))),
              j1 = std::min(ny - 1, int(std::ceil((yhi - f.origin.y()) / f.h - 0.5)));
    const int k0 = std::max(0, int(std::floor((zlo - f.origin.z()) / f.h - 0.5))),
              k1 = std::min(nz - 1, int(std::ceil((zhi - f.origin.z()) / f.h - 0.5)));
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j) {
        const double y = f.origin.y() + (j + 0.5 + kRowNudgeY) * f.h, z = f.origin.z() + (k + 0.5 + kRowNudgeZ) * f.h;
        // 2-D barycentric coordinates of (y, z) in the triangle's projection onto the y-z plane.
        const double w0 = (b.y() - y) * (c.z() - z) - (b.z() - z) * (c.y() - y);
        const double w1 = (c.y() - y) * (a.z() - z) - (c.z() - z) * (a.y() - y);
        const double w2 = (a.y() - y) * (b.z() - z) - (a.z() - z) * (b.y() - y);
        if (!((w0 >= 0 && w1 >= 0 && w2 >= 0) || (w0 <= 0 && w1 <= 0 && w2 <= 0))) continue;
        const double sum = w0 + w1 + w2;
        if (sum == 0) continue;
        const double x = (w0 * a.x() + w1 * b.x() + w2 * c.x()) / sum;
        rows[std::size_t(j) + std::size_t(ny) * k].emplace_back(x, n.x() < 0 ? 1 : -1);  // entering: normal -x
      }
  }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      auto& row = rows[std::size_t(j) + std::size_t(ny) * k];
      std::sort(row.begin(), row.end());
      std::size_t next = 0;
      int winding = 0;
      for (int i = 0; i < nx; ++i) {
        const double x = f.origin.x() + (i + 0.5) * f.h;
        while (next < row.size() && row[next].first < x) winding += row[next++].second;
        if (winding != 0) f.inside[f.cellIndex(i, j, k)] = 1;
      }
    }
}

// Cells a triangle passes within the circumscribed sphere of (radius h sqrt(3) / 2 about the centre).
void markCut(LatticeFill& f, const std::vector<Vec3>& pts, const std::vector<std::array<int, 3>>& tris) {
  const double reach = f.h * std::sqrt(3.0) / 2 * (1 + 1e-9);
  for (const auto& t : tris) {
    const Vec3 &a = pts[t[0]], &b = pts[t[1]], &c = pts[t[2]];
    std::array<int, 3> lo, hi;
    for (int ax = 0; ax < 3; ++ax) {
      const double mn = std::min({a[ax], b[ax], c[ax]}), mx = std::max({a[ax], b[ax], c[ax]});
      lo[ax] = std::max(0, int(std::floor((mn - f.origin[ax]) / f.h)) - 1);
      hi[ax] = std::min(f.cells[ax] - 1, int(std::floor((mx - f.origin[ax]) / f.h)) + 1);
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          char& kept = f.kept[f.cellIndex(i, j, k)];
          if (kept) continue;
          const Vec3 centre = f.origin + f.h * Vec3(i + 0.5, j + 0.5, k + 0.5);
          if ((closestPointOnTriangle(centre, a, b, c) - centre).norm() <= reach) kept = 1;
        }
  }
}

}  // namespace

LatticeFill fillLattice(const std::vector<Vec3>& local, const std::vector<std::array<int, 3>>& triangles, int cells) {
  Eigen::AlignedBox3d box;
  for (const Vec3& p : local) box.extend(p);
  const Vec3 extent = box.sizes();
  LatticeFill f;
  f.h = extent.maxCoeff() / cells;
  for (int a = 0; a < 3; ++a) {
    // As many cells as cover the extent (a hair of round-off is not a cell), centred on the box.
    f.cells[a] = std::max(1, static_cast<int>(std::ceil(extent[a] / f.h - 1e-9)));
    f.origin[a] = box.center()[a] - f.cells[a] * f.h / 2;
  }
  const std::size_t count = std::size_t(f.cells[0]) * f.cells[1] * f.cells[2];
  f.inside.assign(count, 0);
  markInside(f, local, triangles);
  f.kept = f.inside;
  markCut(f, local, triangles);
  for (const Vec3& p : local) {
    std::array<int, 3> c;
    Vec3 t;
    locate(f, p, c, t);
    f.kept[f.cellIndex(c[0], c[1], c[2])] = 1;
  }
  return f;
}

BodySize meshJellySize(std::int64_t cells, std::int64_t points, std::int64_t triangles) {
  const std::int64_t n = cells + 1;
  return {n * n * n, latticeSpringCount({n, n, n}, jellyOffsets()), points + 3 * triangles, triangles};
}

Body buildMeshJelly(const std::string& name, const ModelMesh& model, const MeshJellyParams& p) {
  if (std::pow(p.cells + 1.0, 3) > double(kMaxBodyParticles))
    throw std::length_error("jelly '" + name + "': cells = " + std::to_string(p.cells) + " gives too many particles");
  const std::vector<Vec3> local = localPoints(model, p.placement.scale);
  const LatticeFill f = fillLattice(local, model.triangles, p.cells);
  const std::array<int, 3> dims{f.cells[0] + 1, f.cells[1] + 1, f.cells[2] + 1};
  const auto nodeOf = [&](int i, int j, int k) { return i + dims[0] * (j + dims[1] * k); };

  // A node is a particle when a kept cell touches it; particles in node order (x fastest), as the cube jelly's.
  std::vector<int> node_index(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], -1);
  for (int k = 0; k < f.cells[2]; ++k)
    for (int j = 0; j < f.cells[1]; ++j)
      for (int i = 0; i < f.cells[0]; ++i)
        if (f.kept[f.cellIndex(i, j, k)])
          for (int c = 0; c < 8; ++c) node_index[nodeOf(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2))] = 0;
  int count = 0;
  for (int& id : node_index)
    if (id == 0) id = count++;
    else id = -1;

  Body body = particleBody(name, "jelly", count, p.mass);
  const Eigen::Matrix3d rotation = p.placement.rotation();
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        if (const int id = node_index[nodeOf(i, j, k)]; id >= 0) {
          particle(body.x, id) = p.placement.center + rotation * (f.origin + f.h * Vec3(i, j, k));
          particle(body.v, id) = p.velocity;
        }
  addPartialLatticeSprings(dims, jellyOffsets(), node_index, f.kept, body.x, p.ks, p.kd, body.springs);

  // The surface: model vertex v is surface vertex v; a (vertex, UV) pair met again with another UV adds a vertex.
  SurfaceMesh& s = body.surface;
  s.embedded.resize(local.size());
  for (std::size_t v = 0; v < local.size(); ++v) {
    std::array<int, 3> c;
    Vec3 t;
    locate(f, local[v], c, t);
    EmbeddedPoint& e = s.embedded[v];
    for (int q = 0; q < 8; ++q) {
      const int di = q & 1, dj = q >> 1 & 1, dk = q >> 2;
      e.particle[q] = node_index[nodeOf(c[0] + di, c[1] + dj, c[2] + dk)];
      e.weight[q] = (di ? t.x() : 1 - t.x()) * (dj ? t.y() : 1 - t.y()) * (dk ? t.z() : 1 - t.z());
    }
    s.particle.push_back(int(v));
  }
  s.uv.assign(local.size(), Eigen::Vector2f::Zero());
  std::vector<char> has_uv(local.size(), 0);
  std::map<std::pair<int, std::pair<float, float>>, int> seam;  // (point, uv) -> its extra vertex
  for (std::size_t tri = 0; tri < model.triangles.size(); ++tri) {
    std::array<int, 3> corners = model.triangles[tri];
    if (!model.corner_uv.empty())
      for (int k = 0; k < 3; ++k) {
        const int v = corners[k];
        const Eigen::Vector2f uv = model.corner_uv[tri][k];
        if (!has_uv[v]) {
          has_uv[v] = 1;
          s.uv[v] = uv;
        } else if (s.uv[v] != uv) {
          const auto [it, added] = seam.try_emplace({v, {uv.x(), uv.y()}}, int(s.particle.size()));
          if (added) {
            s.particle.push_back(v);
            s.uv.push_back(uv);
          }
          corners[k] = it->second;
        }
      }
    s.triangles.push_back(corners);
  }
  return body;
}

}  // namespace wobble
