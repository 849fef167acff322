#include "sim/contact/candidates/step_list.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "sim/contact/distance/separation.h"
#include "sim/solver/parallel.h"

namespace wobble::collision {
namespace {
// The step's candidates are found with boxes padded by this fraction of the largest thickness more than the exact
// broad phase's: room for the solves' ends to move from the first one's.
constexpr double kStepMarginFraction = 0.25;
}  // namespace

bool StepList::reuse(Candidates& round, bool may_update) {
  if (!broadPhaseCulls() || !step.valid || step.start.size() != motion_.nxs.size() ||
      step.end.size() != motion_.nxe.size())
    return false;
  if (std::memcmp(step.start.data(), motion_.nxs.data(), sizeof(double) * std::size_t(motion_.nxs.size())) != 0)
    return false;
  if (!((motion_.nxe - step.end).cwiseAbs().maxCoeff() <= step.margin) && !(may_update && update(round))) return false;
  round.step = &step;
  round.drift = 0;
  for (int k = 0; k < nodes_.nodeCount(); ++k)
    round.drift = std::max(round.drift, (particle(motion_.nxe, k) - particle(step.end, k)).norm());
  return true;
}

bool StepList::laterRound(Candidates& round) {
  if (reuse(round, false)) {
    ++counters_.step_rounds;
    return true;
  }
  return search_.broadPhase(round, true);
}

bool StepList::find(Candidates& round) {
  step.margin = kStepMarginFraction * nodes_.max_thickness;
  step.valid = false;
  int found = skins_.stepCandidates(round, 0.5 * nodes_.max_thickness + step.margin);
  if (!found) found = search_.broadPhase(round, false, step.margin) ? 3 : 0;
  if (!found) return false;
  counters_.skin_searches += found == 1;
  step.frames = round.listed;
  step.start = motion_.nxs;
  step.end = motion_.nxe;
  step.vf.swap(round.vf);
  step.ee.swap(round.ee);
  release(round.vf), release(round.ee);  // the last list's room: the round reads the step's lists
  round.step = &step;
  round.drift = 0;
  step.near_min = std::numeric_limits<double>::infinity();
  keepMeasured(round, [&](int k, Kept& out) {
    out.m = measured(round, k);
    out.joined = SIZE_MAX;
    return kept(out.m);
  });
  step.valid = true;
  return true;
}

template <class Fn>
void StepList::keepMeasured(const Candidates& round, Fn&& measure) {
  // Each candidate measured on threads, chunk by chunk; only the kept ones held, with their measures (step_list.h).
  const int n = round.count(), chunk = particleChunk(n), chunks = (n + chunk - 1) / chunk;
  auto& parts = kept_scratch_;
  if (int(parts.size()) < chunks) parts.resize(chunks);
  forEachChunk(n, parallel_, [&](int begin, int end) {
    auto& part = parts[begin / chunk];
    part.clear();
    for (int k = begin; k < end; ++k)
      if (Kept c{k}; measure(k, c)) part.push_back(c);
  });
  std::size_t total = 0;
  for (int c = 0; c < chunks; ++c) total += parts[c].size();
  auto& [closing, hitting, near] = scratch_;
  closing.resize(total), hitting.resize(total), near.resize(total);
  step.closest.resize(total);
  step.joined.resize(total);
  step.near.clear();
  step.closing.clear();
  step.hitting.clear();
  const int vf_count = int(step.vf.size());
  int j = 0, kept_vf = 0;
  for (int c = 0; c < chunks; ++c)
    for (const Kept& e : parts[c]) {
      const int k = e.k;
      if (k < vf_count) step.vf[kept_vf++] = step.vf[k];
      else step.ee[j - kept_vf] = step.ee[k - vf_count];
      step.closest[j] = e.m.closest, step.joined[j] = e.joined;
      closing[j] = e.m.closing, hitting[j] = e.m.hitting, near[j] = e.m.near;
      list(j++);
    }
  step.ee.resize(j - kept_vf), step.vf.resize(kept_vf);
  // The lists kept at their size (most of a broad phase's candidates are dropped), the parts let go.
  step.vf.shrink_to_fit(), step.ee.shrink_to_fit();
  for (auto& part : parts) release(part);
}

StepList::Measure StepList::measured(const Candidates& round, int k) const {
  const PairInfo p = round.info(nodes_, k);
  const auto x = points(motion_.nxs, p.stencil);
  Measure m;
  const Closest& c = m.closest = nearest(p.kind, x);
  double gap = -std::numeric_limits<double>::infinity();  // at the end along the start's direction
  if (c.distance > 0) {
    const double end_gap = gapAlong(c.delta / c.distance, step.end, p.stencil.vertex, p.first());
    if (std::isfinite(end_gap)) gap = end_gap;
  }
  const double eta2 = 2 * kEtaFraction * p.thickness;
  m.closing = c.distance > 0 ? gap - (1 + 1e-5) * p.thickness : std::numeric_limits<double>::infinity();
  m.hitting = c.distance > eta2 ? gap - eta2 : -std::numeric_limits<double>::infinity();
  m.near = c.distance < p.thickness;
  return m;
}

// Any end the candidates serve lies within the margin of step.end along each axis: within sqrt(3) margin.
double StepList::most() const { return 2 * std::sqrt(3.0) * step.margin; }

bool StepList::kept(const Measure& m) const { return m.near || !(m.closing > most()) || !(m.hitting > most()); }

void StepList::list(int j) {
  auto& [closing, hitting, near] = scratch_;
  if (near[j]) step.near.push_back(j), step.near_min = std::min(step.near_min, step.closest[j].distance);
  if (!(closing[j] > most())) step.closing.emplace_back(j, closing[j]);
  if (!(hitting[j] > most())) step.hitting.emplace_back(j, hitting[j]);
}

bool StepList::update(Candidates& round) {
  auto& [beyond, fresh_vf, fresh_ee, merged_vf, merged_ee, from] = update_scratch_;
  beyond.assign(nodes_.nodeCount(), 0);
  for (int k = 0; k < nodes_.nodeCount(); ++k)
    beyond[k] = !((particle(motion_.nxe, k) - particle(step.end, k)).cwiseAbs().maxCoeff() <= step.margin);
  search_.marks.mark(nodes_, beyond);
  VecX end = step.end;
  for (int k = 0; k < nodes_.nodeCount(); ++k)
    if (beyond[k]) particle(end, k) = particle(motion_.nxe, k);
  if (!search_.listPairs(round.cull, end, step.frames.shifts, step.frames.pad, true, false, fresh_vf, fresh_ee))
    return false;
  // The kept candidates (no marked element) and the fresh ones, merged in order; per merged candidate its old index
  // (-1: fresh).
  from.clear();
  mergeUnmarked(step.vf, fresh_vf, search_.marks.vertex, search_.marks.triangle, merged_vf, &from, 0);
  mergeUnmarked(step.ee, fresh_ee, search_.marks.edge, search_.marks.edge, merged_ee, &from, int(step.vf.size()));
  release(fresh_vf), release(fresh_ee);
  if (merged_vf.size() + merged_ee.size() > search_.budget()) return false;
  // Each candidate kept with its measures (an old one: as they were; its boxes did not change), a fresh one measured,
  // and only those a search may test kept (the old ones were: their measures and the margin are the same). Measured
  // in the merged order, they come out in it; near_min is lowered by the fresh ones.
  auto& [closing, hitting, near] = scratch_;
  step.vf.swap(merged_vf), step.ee.swap(merged_ee), step.end.swap(end);
  round.step = &step;  // measured reads the step's lists
  keepMeasured(round, [&](int k, Kept& out) {
    const int i = from[k];
    if (i < 0) {
      out.m = measured(round, k);
      out.joined = SIZE_MAX;
      return kept(out.m);
    }
    out.m = Measure{step.closest[i], closing[i], hitting[i], near[i]};
    out.joined = step.joined[i];
    return true;
  });
  release(merged_vf), release(merged_ee), release(from);  // the old lists, and the merged one's origins
  ++counters_.step_updates;
  return true;
}

}  // namespace wobble::collision
