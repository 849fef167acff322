// The surfaces of the bodies as contact between bodies sees them: their vertices as nodes, each a weighted blend of
// particles (weights summing to 1): one particle of weight 1 for a surface over particles, a lattice cell's 8 particles
// for a mesh jelly's embedded surface (colliders/weighted_points.h). A node's trajectory over a step is the blend of
// its particles' straight trajectories, itself straight: the continuous test holds on it as on a particle's, and an
// impulse on it is handed to its particles by the weights. Built once per system; every stage of the pass reads it.
#pragma once
#include <algorithm>
#include <array>
#include <vector>

#include "sim/body.h"
#include "sim/contact/distance/primitives.h"
#include "sim/solver/stencil.h"
#include "sim/types.h"

namespace wobble::collision {

// A body's surface for the pass: its mesh, where its particles start in the system, its contact parameters.
struct Surface {
  const SurfaceMesh* mesh;
  int first_particle;
  SurfaceContact params;
  double stiffness;  // N/m of the repulsion spring: the body's mean spring stiffness (Bridson 2002, 7.2)
};

// A candidate pair's kind, stencil (its four nodes; weights set where they are known) and what its bodies set.
struct PairInfo {
  Primitive kind;
  Stencil stencil;
  double thickness, friction, stiffness;
  // The first element's nodes: stencil.vertex[0, first()) (a point, or an edge), the second's the rest.
  int first() const { return kind == Primitive::PointTriangle ? 1 : 2; }
};

// The nearest points of a pair's two elements, whose nodes are at x (in stencil order).
inline Closest nearest(Primitive kind, const std::array<Vec3, 4>& x) {
  return kind == Primitive::PointTriangle ? pointTriangle(x[0], x[1], x[2], x[3]) : edgeEdge(x[0], x[1], x[2], x[3]);
}

// The stencil's vertices in a per-node vector (3 per node).
inline std::array<Vec3, 4> points(const VecX& x, const Stencil& s) {
  return {particle(x, s.vertex[0]), particle(x, s.vertex[1]), particle(x, s.vertex[2]), particle(x, s.vertex[3])};
}

struct SurfaceNodes {
  SurfaceNodes(const std::vector<Surface>& surfaces, const VecX& inverse_mass);

  // Node k's particles are node_particle[node_start[k] .. node_start[k + 1]), with their weights. Every node is a
  // vertex of the pass (vertex slot k is node k); triangles and edges are in node indices, each with its body.
  std::vector<int> node_start{0}, node_particle;
  std::vector<double> node_weight;
  std::vector<int> particle_node_start, particle_nodes;  // per particle, the nodes over it (CSR)
  std::vector<int> pass_particles;                       // every particle a node rides on, ascending
  std::vector<double> node_inv_mass;                     // sum w^2 / m over a node's particles
  bool single_particle_nodes = true;  // no surface of embedded points: each node its own particle, of weight 1
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 2>> edges;
  std::vector<int> triangle_body, edge_body, vertex_body;
  std::vector<std::array<int, 1>> single_nodes;  // each node as a one-node element (the vertices' boxes)
  std::vector<SurfaceContact> params;            // per body
  std::vector<double> stiffness;                 // per body
  double max_thickness = 0;

  int nodeCount() const { return int(node_start.size()) - 1; }
  // Node k's blend of a flat per-particle vector s, into out (3 per node); a node of one particle of weight 1 copies.
  void blendNode(const VecX& s, int k, VecX& out) const {
    const int begin = node_start[k], end = node_start[k + 1];
    if (end - begin == 1 && node_weight[begin] == 1) {
      particle(out, k) = particle(s, node_particle[begin]);
      return;
    }
    Vec3 sum = Vec3::Zero();
    for (int j = begin; j < end; ++j) sum += node_weight[j] * particle(s, node_particle[j]);
    particle(out, k) = sum;
  }
  // Every node's blend, on threads when parallel.
  void blendNodes(const VecX& s, VecX& out, bool parallel) const;
  // The particle of node k with the largest weight (for messages).
  int mainParticle(int k) const;
  // The stencil of a pair over nodes with weights w (Stencil), over the nodes' particles: sum_i w_i sum_j W_ij x_j.
  WeightedStencil expand(const Stencil& s, const std::array<double, 4>& w) const;

  bool bodiesMeet(int a, int b) const { return a != b || params[a].self_contact; }
  double pairThickness(int a, int b) const { return std::max(params[a].thickness, params[b].thickness); }
  // The stencil's vertices of a point-triangle (first: the vertex, second: the triangle) or edge-edge pair.
  std::array<int, 4> nodes(Primitive kind, int first, int second) const {
    if (kind == Primitive::PointTriangle) {
      const auto& t = triangles[second];
      return {first, t[0], t[1], t[2]};
    }
    return {edges[first][0], edges[first][1], edges[second][0], edges[second][1]};
  }
  PairInfo info(Primitive kind, int first, int second) const {
    PairInfo p;
    p.kind = kind;
    p.stencil.vertex = nodes(kind, first, second);
    const bool vf = kind == Primitive::PointTriangle;
    const int a = vf ? vertex_body[first] : edge_body[first], b = vf ? triangle_body[second] : edge_body[second];
    p.thickness = pairThickness(a, b);
    p.friction = 0.5 * (params[a].friction + params[b].friction);
    p.stiffness = 0.5 * (stiffness[a] + stiffness[b]);
    return p;
  }
};

}  // namespace wobble::collision
