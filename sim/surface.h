// The renderable surface of a body: fixed topology (vertex -> particle, UVs, triangles), and per-frame positions
// and smooth normals computed from the particle state. Same vertex count and order every frame.
#pragma once
#include <array>
#include <vector>

#include <Eigen/Core>

#include "sim/types.h"

namespace wobble {

// A surface point riding on 8 particles (a mesh jelly's model vertex in its lattice cell, bodies/mesh_jelly.h): the
// trilinear weights sum to 1 and are fixed at build time.
struct EmbeddedPoint {
  std::array<int, 8> particle;  // within its body
  std::array<double, 8> weight;
};

struct SurfaceMesh {
  // vertex -> particle index within its body; when `embedded` is not empty, vertex -> embedded point instead
  std::vector<int> particle;
  std::vector<EmbeddedPoint> embedded;        // empty: the surface is over particles themselves
  std::vector<Eigen::Vector2f> uv;            // per vertex, v up (OBJ convention)
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside

  std::size_t vertexCount() const { return particle.size(); }
};

struct SurfaceFrame {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // area-weighted average over the triangles that share a vertex
};

// Positions and normals of mesh for the body whose first particle is first_particle in the flat state x.
SurfaceFrame evaluateSurface(const SurfaceMesh& mesh, const VecX& x, int first_particle);

}  // namespace wobble
