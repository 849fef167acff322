#include "sim/contact/candidates/skins.h"

#include <algorithm>
#include <limits>

namespace wobble::collision {
namespace {
// The pass's candidates kept across steps (Skin) are found with boxes padded by this fraction of the largest thickness
// more than the exact broad phase's, and serve while every node stays within half of it of the box it swept.
constexpr double kSkinFraction = 0.5;
// Backward Euler's step lists are kept across steps (StepSkin) with each node's interval reaching this fraction of the
// largest thickness beyond its start and end, each way.
constexpr double kNodeSlackFraction = 0.5;
}  // namespace

bool Skins::passCandidates(Candidates& round) {
  const int found = keptCandidates(round, skin, 0);
  if (found == 1) {
    round.from_skin = true;
    ++counters_.skin_passes;
  } else if (found == 2) {
    round.from_skin = true;
    skin.lower.assign(round.vf.size() + round.ee.size(), 0.0);
    skin.lower_valid = false;
  }
  return found != 0;
}

double Skins::skinDrift(std::initializer_list<const VecX*> xs) const {
  double most = 0;
  for (const VecX* x : xs)
    for (int k = 0; k < nodes_.nodeCount(); ++k)
      most = std::max(most, (particle(*x, k) - particle(skin.reference, k)).norm());
  return most;
}

// vf and ee for (nxs, nxe) from a broad phase padded by `margin` more than the exact one:
// k's list when it serves (returns 1), else a new list for k when the step moved every node by less than half k's
// margin (then it likely serves a step or more; returns 2), else the broad phase's (3). 0: over the budget. After a
// list that served no step, the next is found only after a step that moved every node by less than a quarter of the
// margin: a list costs more to find than the exact one (twice the candidates on a collapsed cloth), and a body whose
// every step moves some node by a third to a half of the margin or more (a cloth settling onto itself) otherwise finds
// one nearly every step and leaves it the next.
int Skins::keptCandidates(Candidates& round, Skin& k, double margin) {
  const double skin_margin = kSkinFraction * nodes_.max_thickness;
  if (broadPhaseCulls() && k.valid && k.lo.size() == motion_.nxs.size()) {
    bool inside = true;
    for (Eigen::Index j = 0; j < motion_.nxs.size() && inside; ++j) inside = motion_.sweptWithin(k.lo, k.hi, j);
    if (inside) {
      round.renew(broadPhaseCulls());
      round.vf = k.vf;
      round.ee = k.ee;
      ++k.served;
      return 1;
    }
  }
  k.valid = false;
  if (broadPhaseCulls() && (motion_.nxe - motion_.nxs).cwiseAbs().maxCoeff() < skin_margin / (k.served > 0 ? 2 : 4) &&
      search_.broadPhase(round, false, margin + skin_margin, true)) {
    k.lo = motion_.nxs.cwiseMin(motion_.nxe).array() - skin_margin / 2;
    k.hi = motion_.nxs.cwiseMax(motion_.nxe).array() + skin_margin / 2;
    k.vf = round.vf;
    k.ee = round.ee;
    k.reference = motion_.nxs;
    k.valid = true;
    k.served = 0;
    ++counters_.skin_lists;
    return 2;
  }
  return search_.broadPhase(round, false, margin) ? 3 : 0;
}

// The box and diagonals of an element over its nodes' step skin intervals, padded (fillBoxes).
auto Skins::stepSkinBox(double pad) const {
  return [this, pad](const auto& nodes, int, Box& box_out, Diagonals& diagonals_out) {
    const StepSkin& k = step_skin_;
    box_out = Box{Vec3::Constant(std::numeric_limits<double>::infinity()),
                  Vec3::Constant(-std::numeric_limits<double>::infinity())};
    diagonals_out = Diagonals{};
    for (const int i : nodes) {
      const Vec3 lo = particle(k.lo, i), hi = particle(k.hi, i);
      box_out.lo = box_out.lo.cwiseMin(lo);
      box_out.hi = box_out.hi.cwiseMax(hi);
      diagonals_out.include(lo, hi);
    }
    box_out.lo.array() -= pad;
    box_out.hi.array() -= -pad;
    for (int j = 0; j < 6; ++j) diagonals_out.lo[j] -= 2 * pad, diagonals_out.hi[j] += 2 * pad;
  };
}

int Skins::stepCandidates(Candidates& round, double pad) {
  StepSkin& k = step_skin_;
  if (!broadPhaseCulls()) return k.valid = false, 0;  // the exact broad phase every time
  round.renew(broadPhaseCulls());
  const int n = nodes_.nodeCount();
  if (k.lo.size() != motion_.nxs.size()) k.valid = false;
  const double slack = kNodeSlackFraction * nodes_.max_thickness;
  int result = 1;
  if (k.valid) {
    k.outside.assign(n, 0);
    int count = 0;
    for (int i = 0; i < n; ++i) {
      bool inside = true;
      for (int j = 3 * i; j < 3 * i + 3; ++j) inside = inside && motion_.sweptWithin(k.lo, k.hi, j);
      k.outside[i] = !inside;
      count += !inside;
    }
    k.valid = count <= n / 4 && (count == 0 || updateStepSkin(pad, slack, round.cull));
  }
  if (!k.valid) {
    int fast = 0;
    for (int i = 0; i < n; ++i)
      fast += !((particle(motion_.nxe, i) - particle(motion_.nxs, i)).cwiseAbs().maxCoeff() <= slack);
    if (fast > n / 8) return 0;
    k.lo = motion_.nxs.cwiseMin(motion_.nxe).array() - slack;
    k.hi = motion_.nxs.cwiseMax(motion_.nxe).array() + slack;
    fillBoxes(nodes_, search_.marks, k.boxes, false, parallel_, stepSkinBox(pad));
    if (!search_.findPairs(
            k.boxes, round.cull, [&](int a, int b) { return nodes_.bodiesMeet(a, b); }, false, false, k.vf, k.ee, 0))
      return 0;
    ++counters_.broad_phases;
    counters_.candidates += long(k.vf.size() + k.ee.size());
    ++counters_.skin_lists;
    k.valid = true;
    result = 2;
  }
  // The skin's pairs whose boxes and diagonals for this step meet.
  round.listed.pad = pad;
  round.listed.shifts.clear();
  search_.fillSweptBoxes(round.cull, motion_.nxe, nullptr, pad);
  keepPairs(k.vf, round.vf, [&](int v, int t) {
    return search_.boxes.vertex[v].overlaps(search_.boxes.triangle[t]) &&
           !diagonallyApart(search_.boxes.vertex_diagonals[v], search_.boxes.triangle_diagonals[t]);
  });
  keepPairs(k.ee, round.ee, [&](int e, int f) {
    return search_.boxes.edge[e].overlaps(search_.boxes.edge[f]) &&
           !diagonallyApart(search_.boxes.edge_diagonals[e], search_.boxes.edge_diagonals[f]);
  });
  return result;
}

// The step skin's nodes marked outside get new intervals, and the pairs of the elements holding one are found
// again. False: over the budget.
bool Skins::updateStepSkin(double pad, double slack, bool cull) {
  StepSkin& k = step_skin_;
  for (int i = 0; i < nodes_.nodeCount(); ++i)
    if (k.outside[i])
      for (int j = 3 * i; j < 3 * i + 3; ++j)
        k.lo[j] = std::min(motion_.nxs[j], motion_.nxe[j]) - slack,
        k.hi[j] = std::max(motion_.nxs[j], motion_.nxe[j]) + slack;
  search_.marks.mark(nodes_, k.outside);
  fillBoxes(nodes_, search_.marks, k.boxes, true, parallel_, stepSkinBox(pad));
  if (!search_.findPairs(
          k.boxes, cull, [&](int a, int b) { return nodes_.bodiesMeet(a, b); }, true, false, k.fresh_vf, k.fresh_ee, 0))
    return false;
  ++counters_.broad_phases;
  ++counters_.skin_updates;
  counters_.candidates += long(k.fresh_vf.size() + k.fresh_ee.size());
  mergeUnmarked(k.vf, k.fresh_vf, search_.marks.vertex, search_.marks.triangle, k.merged);
  k.vf.swap(k.merged);
  mergeUnmarked(k.ee, k.fresh_ee, search_.marks.edge, search_.marks.edge, k.merged);
  k.ee.swap(k.merged);
  release(k.fresh_vf), release(k.fresh_ee), release(k.merged);
  return k.vf.size() + k.ee.size() <= search_.budget();
}

// The pairs of `in` for which keep(first, second) holds, into out in order (on threads).
template <class Keep>
void Skins::keepPairs(const PairList& in, PairList& out, Keep&& keep) {
  const int n = int(in.size()), chunk = particleChunk(n), chunks = (n + chunk - 1) / chunk;
  std::vector<int> count(chunks + 1, 0);
  std::vector<char>& kept = keep_scratch_;  // per pair
  kept.resize(n);
  forEachChunk(n, parallel_, [&](int begin, int end) {
    int c = 0;
    for (int j = begin; j < end; ++j) c += kept[j] = keep(in[j].first, in[j].second);
    count[begin / chunk + 1] = c;
  });
  for (int c = 0; c < chunks; ++c) count[c + 1] += count[c];
  out.resize(count[chunks]);
  forEachChunk(n, parallel_, [&](int begin, int end) {
    int at = count[begin / chunk];
    for (int j = begin; j < end; ++j)
      if (kept[j]) out[at++] = in[j];
  });
}

}  // namespace wobble::collision
