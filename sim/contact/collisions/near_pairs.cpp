// Backward Euler's searches for the pairs its solve takes in (BodyCollisions::nearPairs).
#include <algorithm>
#include <cstdint>

#include "sim/contact/ccd/ccd.h"
#include "sim/contact/collisions/body_collisions.h"
#include "sim/contact/collisions/body_collisions_impl.h"
#include "sim/contact/distance/separation.h"
#include "sim/solver/parallel.h"

namespace wobble::collision {

bool BodyCollisions::nearPairs(const VecX& x0, const VecX& x1, std::vector<ContactPair>& out, PairJoin& join) {
  Impl& s = *impl_;
  if (!x1.allFinite()) return false;
  if (s.clearance.covers(x0, x1)) {  // no pair can be within the thickness at x1 or collide on the way
    ++stats_.searches_skipped;
    return false;
  }
  s.nodes.blendNodes(x0, s.motion.nxs, s.parallel);
  s.nodes.blendNodes(x1, s.motion.nxe, s.parallel);
  // The shortcuts off: the exact broad phase, every time; so too when the step's list, padded by its margin, would be
  // over the candidate budget (the exact one may fit, and then the pass after the step goes on: the solve must have
  // its pairs). Over the budget even so: no pairs (the pass after the step stops the run).
  if (!broadPhaseCulls() ? !s.search.broadPhase(s.round)
                         : !s.steps.reuse(s.round) && !s.steps.find(s.round) && !s.search.broadPhase(s.round))
    return false;
  // With the step's candidates: those apart at the start whose gap at x1 may be within the thickness.
  const auto* only = s.round.step ? s.round.subsetOf(s.steps.step.closing) : nullptr;
  const std::size_t before = out.size();
  s.known.assign(out);  // the pairs already in out
  // A candidate whose pair an earlier search of this step put in out (the same list of candidates), and which is
  // still there, is in out: it leaves the subset before its tests and the set's lookup, as the lookup would drop it.
  // (A step's later searches find the pairs the earlier ones handed over so.)
  if (only) {
    const auto still_in_out = [&](int k) {
      const std::size_t at = s.steps.step.joined[k];
      return at < before && ContactPairSet::same(out[at].element, s.round.pairNodes(s.nodes, k));
    };
    s.round.subset.erase(std::remove_if(s.round.subset.begin(), s.round.subset.end(), still_in_out),
                         s.round.subset.end());
  }
  // Each candidate on threads (gather keeps the pair order): its nearest points at x0, then its gap at x1. What
  // joins is gathered small (the candidate, its weights and normal) and expanded into out after: a pair is 152 bytes
  // (472 when its stencil held room for 32 particles in place, and copying tens of thousands of them through
  // temporaries cost more than the tests).
  struct Joining {
    int k;
    std::array<double, 4> w;
    Vec3 normal;
  };
  const std::vector<Joining> found = s.round.gather(
      s.nodes, s.parallel,
      [&](int k, const PairInfo& p, std::size_t& held_back) -> std::optional<Joining> {
        const auto x = points(s.motion.nxs, p.stencil);
        const Closest c = s.round.startClosest(k, p.kind, x);
        if (!(c.distance > 0)) return std::nullopt;  // touching at the start: no direction (the post-step pass has it)
        const Vec3 normal = c.delta / c.distance;
        // The gap at x1 from the nodes first (cheap, and most candidates are far from closing); the pair's own, over
        // its particles, decides (it differs in rounding only, far below this margin).
        Vec3 end_relative = Vec3::Zero();
        for (int i = 0; i < 4; ++i) end_relative += c.w[i] * particle(s.motion.nxe, p.stencil.vertex[i]);
        const double node_gap = normal.dot(end_relative) - p.thickness;
        if (node_gap > 1e-6 * p.thickness) return std::nullopt;
        if (before > 0 && s.known.contains(p.stencil.vertex)) return std::nullopt;  // (an empty out holds none)
        // Where every node is one particle of weight 1 the pair's own gap is the nodes' to the bit (the same particles,
        // weights and sums): no pair built to find it.
        const double gap =
            s.nodes.single_particle_nodes
                ? node_gap
                : ContactPair{p.stencil.vertex, s.nodes.expand(p.stencil, c.w), normal, p.thickness, p.friction}.gap(
                      x1);
        if (!(gap < 0)) return std::nullopt;
        // The linearized gap of a pair far apart at x0 says little: only a pair that does come within the thickness at
        // x1 (or crosses on the way) joins. The start's nearest points are points of the elements at x1 too, so the
        // elements are no further apart there than end_relative is long: within the thickness (less a hair, for the
        // rounding of the exact test it spares), they are (97 in 100 of the pairs tested here on a cloth lying on
        // itself).
        if (!(end_relative.squaredNorm() < (1 - 1e-9) * (1 - 1e-9) * p.thickness * p.thickness)) {
          const auto e = points(s.motion.nxe, p.stencil);
          const Closest end = nearest(p.kind, e);
          if (!(end.distance < p.thickness) && !firstHit(p.kind, x, e, kEtaFraction * p.thickness)) return std::nullopt;
        }
        if (!join.hands(p.stencil.vertex, c.distance - p.thickness, gap, p.thickness)) {
          ++held_back;
          return std::nullopt;
        }
        return Joining{k, c.w, normal};
      },
      only, &join.held_back);
  out.resize(before + found.size());
  forEachChunk(int(found.size()), s.parallel, [&](int begin, int end) {
    for (int j = begin; j < end; ++j) {
      if (only) s.steps.step.joined[found[j].k] = before + j;
      const PairInfo p = s.round.info(s.nodes, found[j].k);
      out[before + j] = ContactPair{p.stencil.vertex, s.nodes.expand(p.stencil, found[j].w), found[j].normal,
                                    p.thickness, p.friction};
    }
  });
  return out.size() > before;
}

}  // namespace wobble::collision
