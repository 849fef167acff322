#include "sim/contact/ccd/detection.h"

#include <algorithm>
#include <optional>

#include "sim/contact/ccd/ccd.h"
#include "sim/contact/distance/separation.h"

namespace wobble::collision {
namespace {
// A collision impulse leaves at most this fraction of the approach speed as separation (no restitution beyond it),
// and aims to end the step this fraction of the thickness apart.
constexpr double kSeparation = 0.1, kEndGapFraction = 0.01;
}  // namespace

std::vector<Contact> Detection::detect(Candidates& round, ImpactZones* zones, bool all) {
  const bool within_zones = zones;
  if (within_zones) zones->findRoots(nodes_);
  // With the step's candidates: those whose distance may come within eta along the step.
  const auto* only = round.step ? round.subsetOf(round.step->hitting) : nullptr;
  // The skin's candidates: those its bounds keep further apart than twice eta all along the step are skipped.
  const bool skip = all && round.from_skin && skins_.skin.lower_valid;
  const double drifted = skip ? 2 * skins_.skinDrift({&motion_.nxs, &motion_.nxe}) : 0;
  std::vector<Contact> hits = round.gather(
      nodes_, parallel_,
      [&](int k, const PairInfo& p) -> std::optional<Contact> {
        if (skip && skins_.skin.lower[k] - drifted > 2 * kEtaFraction * p.thickness) return std::nullopt;
        if (!all) {
          bool moved = false;
          for (const int i : p.stencil.vertex) moved |= motion_.dirty[i] != 0;
          if (!moved) return std::nullopt;
        }
        if (within_zones && zones->inOneZone(nodes_, p.stencil)) return std::nullopt;
        const auto& q = p.stencil.vertex;
        const int first = p.first();
        // Two filters, the cheaper first (one direction where the nearest points at the start are known, else three
        // axes): the step's list carries them for every candidate, repulsion finds them for the round's first test.
        const Closest* start = round.step                         ? &round.step->closest[k]
                               : all && round.round_closest_valid ? &round.round_closest[k]
                                                                  : nullptr;
        if (round.cull && start && apartAlongNearest(motion_.nxs, motion_.nxe, *start, q, first, p.thickness))
          return std::nullopt;
        if (round.cull &&
            apartAllStep(motion_.nxs, motion_.nxe, q.data(), first, q.data() + first, 4 - first, p.thickness))
          return std::nullopt;
        const auto hit = firstHit(p.kind, points(motion_.nxs, p.stencil), points(motion_.nxe, p.stencil),
                                  kEtaFraction * p.thickness);
        if (!hit) return std::nullopt;
        return Contact{k, hit->at, hit->normal, hit->t};
      },
      only);
  std::fill(motion_.dirty.begin(), motion_.dirty.end(), 0);
  return hits;
}

void Detection::impulses(const Candidates& round, const std::vector<Contact>& hits, double h) {
  for (const Contact& c : hits) {
    const PairInfo p = round.info(nodes_, c.pair);
    const double un = c.normal.dot(motion_.relativeVelocity(p.stencil, c.at.w));
    if (un >= 0) continue;  // an earlier impulse of this round already separated it
    const double left = std::max(1 - c.t, 1e-6) * h;
    const double target = std::min(kSeparation * -un, kEndGapFraction * p.thickness / left);
    motion_.applyImpulse(nodes_, inv_mass_, p.stencil, c.at.w, (target - un) * c.normal, h);
  }
}

}  // namespace wobble::collision
