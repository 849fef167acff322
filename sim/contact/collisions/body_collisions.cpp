#include "sim/contact/collisions/body_collisions.h"

#include "sim/contact/collisions/body_collisions_impl.h"

namespace wobble::collision {

BodyCollisions::BodyCollisions(const std::vector<Surface>& surfaces, const VecX& inverse_mass, Settings settings,
                               bool parallel)
    : impl_(std::make_unique<Impl>(surfaces, inverse_mass, settings, parallel, stats_)) {}

BodyCollisions::~BodyCollisions() = default;

bool BodyCollisions::needed(const std::vector<Surface>& surfaces) {
  if (surfaces.size() > 1) return true;
  return !surfaces.empty() && surfaces[0].params.self_contact;
}

std::optional<Failure> BodyCollisions::resolve(const VecX& x0, VecX& x1, VecX& v1, double h, PassOptions options) {
  const bool repulsion = options.repulsion, resting = options.resting;
  Impl& s = *impl_;
  if (s.clearance.covers(x0, x1,
                         {.final_pass = true,
                          .continues = options.continues})) {  // (x1 finite: a blow-up is not covered)
    ++stats_.passes, ++stats_.passes_skipped;
    return std::nullopt;
  }
  if (!x1.allFinite() || !v1.allFinite()) return std::nullopt;  // a blow-up: Simulation reports it next
  ++stats_.passes;
  const Stats before = stats_;
  const Eigen::Index n = x0.size();
  s.motion.xs = x0;
  s.motion.xe = x1;
  s.motion.vbar = (x1 - x0) / h;
  s.motion.vbar0 = s.motion.vbar;
  s.nodes.blendNodes(x0, s.motion.nxs, s.parallel);
  s.nodes.blendNodes(x1, s.motion.nxe, s.parallel);
  s.nodes.blendNodes(s.motion.vbar, s.motion.nvbar, s.parallel);
  s.motion.changed.assign(n / 3, 0);
  s.motion.dirty.assign(s.nodes.nodeCount(), 0);
  if (!s.steps.reuse(s.round) && !s.skins.passCandidates(s.round))
    return s.search.overwhelmedFailure();  // an implicit solve's, or the pass's
  s.repulsion.repel(s.round, h, stats_, repulsion, resting);

  std::optional<Failure> failure;
  bool all = true, clean = false;  // the first detection tests every pair: repulsion moved only some
  std::vector<Contact> hits;
  for (int round = 0; round < s.settings.ccd_iterations; ++round) {
    if (round > 0 && !s.steps.laterRound(s.round)) return s.search.overwhelmedFailure();
    hits = s.detection.detect(s.round, nullptr, all);
    all = false;
    if (hits.empty()) {
      clean = true;
      break;
    }
    stats_.ccd_hits += long(hits.size());
    s.detection.impulses(s.round, hits, h);
  }
  if (!clean) {  // the last round's impulses are not checked yet
    if (all ? !s.search.broadPhase(s.round) : !s.steps.laterRound(s.round)) return s.search.overwhelmedFailure();
    hits = s.detection.detect(s.round, nullptr, all);
  }
  if (!hits.empty()) {
    ++stats_.zone_activations;
    s.zones.reset(int(n / 3));
    int round = 0;
    for (; round < s.settings.zone_iterations && !hits.empty(); ++round) {
      stats_.largest_zone = std::max(stats_.largest_zone, s.zones.rigidify(s.round, hits, h));
      ++stats_.zone_rounds;
      if (!s.search.broadPhase(s.round, true)) return s.search.overwhelmedFailure();
      hits = s.detection.detect(s.round, &s.zones, false);
    }
    if (!hits.empty()) {
      const PairInfo p = s.round.info(s.nodes, hits[0].pair);
      std::ostringstream why;
      std::array<int, 4> q;  // each vertex by its particle (of an embedded point: the one of largest weight)
      for (int i = 0; i < 4; ++i) q[i] = s.nodes.mainParticle(p.stencil.vertex[i]);
      why << hits.size() << (hits.size() > 1 ? " collisions" : " collision") << " between body surfaces left after "
          << round << (round > 1 ? " rounds" : " round") << " of rigid impact zones (the first: ";
      if (p.kind == Primitive::PointTriangle)
        why << "particle " << q[0] << " against the triangle of particles " << q[1] << ", " << q[2] << ", " << q[3];
      else
        why << "the edge of particles " << q[0] << " and " << q[1] << " against the edge of particles " << q[2]
            << " and " << q[3];
      why << " at " << hits[0].t << " of the step)";
      failure = Failure{q[0], why.str()};
    }
  }
  for (Eigen::Index i = 0; i < n / 3; ++i)
    if (s.motion.changed[i]) {
      particle(x1, i) = particle(s.motion.xe, i);
      particle(v1, i) += particle(s.motion.vbar, i) - particle(s.motion.vbar0, i);
    }
  if (repulsion && resting && !failure) s.repulsion.settle(v1);
  s.clearance.passed(stats_.contacts > before.contacts || stats_.ccd_hits > before.ccd_hits ||
                     stats_.zone_activations > before.zone_activations || stats_.min_distance < before.min_distance);
  return failure;
}

}  // namespace wobble::collision
