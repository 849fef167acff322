#include "sim/contact/surface_nodes.h"

#include "sim/solver/parallel.h"
#include "sim/surface.h"

namespace wobble::collision {

SurfaceNodes::SurfaceNodes(const std::vector<Surface>& surfaces, const VecX& inv_mass) {
  const int n = int(inv_mass.size());
  for (std::size_t b = 0; b < surfaces.size(); ++b) {
    const Surface& surface = surfaces[b];
    const SurfaceMesh& mesh = *surface.mesh;
    params.push_back(surface.params);
    stiffness.push_back(surface.stiffness);
    max_thickness = std::max(max_thickness, surface.params.thickness);
    // The body's nodes: the particles (or embedded points) its triangles use, ascending; a triangle with two
    // corners on one is left out.
    std::vector<std::array<int, 3>> body_triangles;
    for (const auto& t : mesh.triangles) {
      const std::array<int, 3> p{mesh.particle[t[0]], mesh.particle[t[1]], mesh.particle[t[2]]};
      if (p[0] != p[1] && p[1] != p[2] && p[0] != p[2]) body_triangles.push_back(p);
    }
    std::vector<int> used;
    for (const auto& t : body_triangles) used.insert(used.end(), t.begin(), t.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    std::vector<int> node(used.empty() ? 0 : used.back() + 1, -1);
    single_particle_nodes = single_particle_nodes && mesh.embedded.empty();
    for (const int u : used) {
      node[u] = nodeCount();
      vertex_body.push_back(int(b));
      if (mesh.embedded.empty()) {
        node_particle.push_back(surface.first_particle + u);
        node_weight.push_back(1.0);
      } else {
        const EmbeddedPoint& e = mesh.embedded[u];
        for (int k = 0; k < 8; ++k)
          if (e.weight[k] != 0) {
            node_particle.push_back(surface.first_particle + e.particle[k]);
            node_weight.push_back(e.weight[k]);
          }
      }
      node_start.push_back(int(node_particle.size()));
    }
    std::vector<std::array<int, 2>> body_edges;
    for (const auto& t : body_triangles) {
      const std::array<int, 3> p{node[t[0]], node[t[1]], node[t[2]]};
      triangles.push_back(p);
      triangle_body.push_back(int(b));
      for (int k = 0; k < 3; ++k)
        body_edges.push_back({std::min(p[k], p[(k + 1) % 3]), std::max(p[k], p[(k + 1) % 3])});
    }
    std::sort(body_edges.begin(), body_edges.end());
    body_edges.erase(std::unique(body_edges.begin(), body_edges.end()), body_edges.end());
    edges.insert(edges.end(), body_edges.begin(), body_edges.end());
    edge_body.insert(edge_body.end(), body_edges.size(), int(b));
  }
  // Per particle its nodes, and the nodes' inverse masses.
  particle_node_start.assign(n + 1, 0);
  for (const int p : node_particle) ++particle_node_start[p + 1];
  for (int p = 0; p < n; ++p) particle_node_start[p + 1] += particle_node_start[p];
  particle_nodes.resize(node_particle.size());
  std::vector<int> fill(particle_node_start.begin(), particle_node_start.end() - 1);
  node_inv_mass.assign(nodeCount(), 0.0);
  for (int k = 0; k < nodeCount(); ++k)
    for (int j = node_start[k]; j < node_start[k + 1]; ++j) {
      particle_nodes[fill[node_particle[j]]++] = k;
      node_inv_mass[k] += node_weight[j] * node_weight[j] * inv_mass[node_particle[j]];
    }
  for (int p = 0; p < n; ++p)
    if (particle_node_start[p + 1] > particle_node_start[p]) pass_particles.push_back(p);
  single_nodes.resize(nodeCount());
  for (int k = 0; k < nodeCount(); ++k) single_nodes[k] = {k};
}

void SurfaceNodes::blendNodes(const VecX& s, VecX& out, bool parallel) const {
  out.resize(3 * nodeCount());
  forEachChunk(nodeCount(), parallel, [&](int begin, int end) {
    for (int k = begin; k < end; ++k) blendNode(s, k, out);
  });
}

int SurfaceNodes::mainParticle(int k) const {
  int best = node_start[k];
  for (int j = node_start[k]; j < node_start[k + 1]; ++j)
    if (node_weight[j] > node_weight[best]) best = j;
  return node_particle[best];
}

WeightedStencil SurfaceNodes::expand(const Stencil& s, const std::array<double, 4>& w) const {
  WeightedStencil out;
  for (int i = 0; i < 4; ++i)
    for (int j = node_start[s.vertex[i]]; j < node_start[s.vertex[i] + 1]; ++j)
      out.add(node_particle[j], w[i] * node_weight[j]);
  return out;
}

}  // namespace wobble::collision
