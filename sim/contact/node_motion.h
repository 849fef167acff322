// The pass's trajectories over one step (collisions/body_collisions.h): each particle moves along x0 + s h vbar, s in
// [0, 1], and each node (surface_nodes.h) along the blend of its particles'. The stages change vbar only; this keeps
// the particles' and the nodes' values in step with each other.
#pragma once
#include <algorithm>
#include <array>
#include <vector>

#include "sim/contact/surface_nodes.h"
#include "sim/types.h"

namespace wobble::collision {

struct NodeMotion {
  VecX xs;                     // the step's start positions
  VecX vbar, vbar0, xe;        // trajectory velocity (changed and at the start), trajectory end
  VecX nxs, nxe, nvbar;        // the same of the nodes (blends of the particles')
  std::vector<char> changed;   // per particle: vbar changed this step
  std::vector<char> dirty;     // per node: moved since the last detection
  std::vector<int> node_mark;  // per node: the last impulse that refreshed it (refreshNodes)
  int mark = 0;

  // After particles' vbar and xe changed: their nodes' nvbar and nxe again, each node once, marked dirty.
  template <class Particles>
  void refreshNodes(const SurfaceNodes& nodes, const Particles& moved) {
    ++mark;
    for (const int p : moved)
      for (int j = nodes.particle_node_start[p]; j < nodes.particle_node_start[p + 1]; ++j) {
        const int k = nodes.particle_nodes[j];
        if (node_mark[k] == mark) continue;
        node_mark[k] = mark;
        nodes.blendNode(vbar, k, nvbar);
        nodes.blendNode(xe, k, nxe);
        dirty[k] = 1;
      }
  }
  // Whether coordinate j of the nodes, swept over the step (nxs to nxe), lies within [lo[j], hi[j]].
  bool sweptWithin(const VecX& lo, const VecX& hi, Eigen::Index j) const {
    return std::min(nxs[j], nxe[j]) >= lo[j] && std::max(nxs[j], nxe[j]) <= hi[j];
  }
  // The relative velocity sum w_i vbar_i of a pair's nodes.
  Vec3 relativeVelocity(const Stencil& s, const std::array<double, 4>& w) const {
    Vec3 u = Vec3::Zero();
    for (int i = 0; i < 4; ++i) u += w[i] * particle(nvbar, s.vertex[i]);
    return u;
  }
  // Changes the relative velocity sum w_i vbar_i by dv, split by the weights and inverse masses over the vertices'
  // particles (an impulse along the pair's stencil of particles: the vertices' own mass 1 / sum W^2 / m is in it).
  void applyImpulse(const SurfaceNodes& nodes, const VecX& inv_mass, const Stencil& s, const std::array<double, 4>& w,
                    const Vec3& dv, double h);
};

}  // namespace wobble::collision
