// The candidate search (sim/contact/candidates/search.h) against a brute-force count over the mesh's elements.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <vector>

#include "sim/bodies/cloth.h"
#include "sim/contact/candidates/search.h"
#include "sim/contact/collisions/body_collisions.h"

namespace wobble {
namespace {

// A flat 9 x 9 cloth surface (spacing 0.1 m) with self-contact, its rows j < 4 pinned, the others free, at rest.
struct PinnedRows {
  static Body cloth() {
    ClothParams p;
    p.nx = p.ny = 9;
    p.size_x = p.size_y = 0.8;
    for (int i = 0; i < 4 * 9; ++i) p.pinned.push_back(i);
    return buildCloth("cloth", p);
  }
  static VecX inverseMass(const Body& b) {
    VecX w(b.particleCount());
    for (int i = 0; i < b.particleCount(); ++i) w[i] = b.pinned[i] ? 0.0 : 1.0 / b.mass[i];
    return w;
  }
  Body body = cloth();  // (the members below are made in this order, each from those above)
  std::vector<collision::Surface> surfaces{{&body.surface, 0, SurfaceContact{0.02, 0.3, true}, 1000.0}};
  VecX inverse_mass = inverseMass(body);
  collision::Stats stats;
  collision::SurfaceNodes nodes{surfaces, inverse_mass};
  collision::NodeMotion motion;
  collision::Settings settings;
  collision::CandidateSearch search{nodes, motion, settings, false, stats};
};

struct Count {
  long all = 0;     // pairs of elements sharing no vertex whose padded boxes overlap
  long pinned = 0;  // of them, those whose vertices are all pinned
};

// Brute force over the surface mesh itself: every vertex against every triangle and every edge against every other
// edge, each box the bounds of the element's corners padded by pad.
Count bruteForce(const Body& body, const VecX& inverse_mass, double pad) {
  const SurfaceMesh& mesh = body.surface;
  const auto at = [&](int v) { return Vec3(body.x.segment<3>(3 * mesh.particle[v])); };
  const auto pinned = [&](int v) { return inverse_mass[mesh.particle[v]] == 0; };
  std::set<std::array<int, 2>> edge_set;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) edge_set.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  const std::vector<std::array<int, 2>> edges(edge_set.begin(), edge_set.end());
  const auto overlap = [&](const std::vector<int>& a, const std::vector<int>& b) {
    for (int axis = 0; axis < 3; ++axis) {
      double a_lo = 1e300, a_hi = -1e300, b_lo = 1e300, b_hi = -1e300;
      for (const int v : a) a_lo = std::min(a_lo, at(v)[axis]), a_hi = std::max(a_hi, at(v)[axis]);
      for (const int v : b) b_lo = std::min(b_lo, at(v)[axis]), b_hi = std::max(b_hi, at(v)[axis]);
      if (a_hi + pad < b_lo - pad || b_hi + pad < a_lo - pad) return false;
    }
    return true;
  };
  Count c;
  const auto tally = [&](const std::vector<int>& a, const std::vector<int>& b) {
    for (const int u : a)
      if (std::find(b.begin(), b.end(), u) != b.end()) return;
    if (!overlap(a, b)) return;
    ++c.all;
    if (std::all_of(a.begin(), a.end(), pinned) && std::all_of(b.begin(), b.end(), pinned)) ++c.pinned;
  };
  for (int v = 0; v < int(mesh.particle.size()); ++v)
    for (const auto& t : mesh.triangles) tally({v}, {t[0], t[1], t[2]});
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (std::size_t f = e + 1; f < edges.size(); ++f) tally({edges[e][0], edges[e][1]}, {edges[f][0], edges[f][1]});
  return c;
}

// The pairs of pinned nodes only are dropped before any other test and counted (Stats::pinned_pairs): they never move,
// so no impulse could act on them. In one broad phase over the cloth at rest, with the culls and without, the count is
// the brute force's; without the culls the pairs listed are the rest of the brute force's (nothing else is dropped).
TEST(CandidateSearch, DropsAndCountsThePairsOfPinnedNodesOnly) {
  PinnedRows c;
  const double pad = 0.5 * c.nodes.max_thickness;  // the broad phase's, without a margin
  const Count expected = bruteForce(c.body, c.inverse_mass, pad);
  // A property of the mesh, not of the pad: the boxes of a flat grid's elements touch or lie a spacing apart.
  EXPECT_EQ(expected.pinned, bruteForce(c.body, c.inverse_mass, 0.3 * 0.1).pinned);
  ASSERT_GT(expected.pinned, 100);
  ASSERT_GT(expected.all, expected.pinned);
  c.nodes.blendNodes(c.body.x, c.motion.nxs, false);
  c.motion.nxe = c.motion.nxs;
  for (const bool cull : {true, false}) {
    SCOPED_TRACE(cull ? "culls on" : "culls off");
    collision::setBroadPhaseCulls(cull);
    collision::Candidates round;
    const long before = c.stats.pinned_pairs;
    ASSERT_TRUE(c.search.broadPhase(round));
    collision::setBroadPhaseCulls(true);
    EXPECT_EQ(c.stats.pinned_pairs - before, expected.pinned);
    if (!cull) {
      EXPECT_EQ(long(round.vf.size() + round.ee.size()), expected.all - expected.pinned);
    }
  }
}

}  // namespace
}  // namespace wobble
