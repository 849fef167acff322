// The candidates value: the pairs of surface elements a round of the pass between bodies (or a search of backward
// Euler's) tests, handed from the search that lists them (search.h: a broad phase; step_list.h and skins.h: lists kept
// through a step's solves or across steps) to the stages that test them (collisions/repulsion.h, ccd/detection.h,
// collisions/near_pairs.cpp). Point-triangle pairs (a vertex slot and a triangle) first, then edge-edge pairs, each
// list ascending; candidate k indexes the two lists one after the other.
#pragma once
#include <algorithm>
#include <limits>
#include <numeric>
#include <optional>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sim/contact/release.h"
#include "sim/contact/surface_nodes.h"

namespace wobble::collision {

using PairList = std::vector<std::pair<int, int>>;

// A candidate pair found near (proximity: repulsion) or colliding (hit: continuous detection).
struct Contact {
  int pair;  // index into the round's candidates
  Closest at;
  Vec3 normal;
  double t;  // hit time (0 for a proximity)
};

// How a broad phase found its lists: the frames its boxes were swept in (empty: the world's; else a shift per body,
// search.h) and their padding.
struct Frames {
  std::vector<Vec3> shifts;
  double pad = 0;
};

// The step's candidates, kept through backward Euler's solves (nearPairs) and the pass after the step (resolve):
// found once for the swept boxes from the start to the first solve's end, padded by a margin more, with each pair's
// nearest points at the start (step_list.h says when they stand and how they are brought up to date).
struct StepCandidates {
  bool valid = false;
  VecX start, end;  // nxs and nxe they were found for
  double margin = 0;
  PairList vf, ee;
  std::vector<Closest> closest;  // at the start, per candidate (vf, then ee)
  // The candidates each search may test, with the drift up to which they need no test (each search then takes those
  // whose slack is at most 2 drift): those within the thickness at the start (repel); those apart at the start whose
  // gap at the end may come within the thickness (nearPairs); those whose distance may come within twice eta along
  // the step (detect). A candidate with slack above what any drift within the margin allows is left out.
  std::vector<int> near;
  std::vector<std::pair<int, double>> closing, hitting;
  // The smallest start distance over the candidates within the thickness there (near: repel's statistic).
  double near_min = std::numeric_limits<double>::infinity();
  // Per candidate, where nearPairs put its pair in out at this step (SIZE_MAX: nowhere yet).
  std::vector<std::size_t> joined;
  // How the list was found: the frames and padding of its boxes, swept from start to end (a list the step skin served
  // is cut down to such a broad phase's, in the world's frame). StepList::update brings it to a new end.
  Frames frames;
};

struct Candidates {
  PairList vf, ee;  // a broad phase's lists, or a kept list's
  // How a broad phase found vf and ee (the step skin's list, cut down to a broad phase's in the world's frame, sets it
  // too). The pass's list kept from an earlier step (Skins::kept) leaves it as it was: it only serves the pass.
  Frames listed;
  const StepCandidates* step = nullptr;  // set: the step's lists are the candidates (vf and ee are not used)
  double drift = 0;                      // with step: the largest distance of a node's end from step->end
  bool from_skin = false;                // vf and ee are the pass's skin's (skins.h)
  bool cull = true;                      // setBroadPhaseCulls, read once a round
  // The round's nearest points at the start, per candidate (a NaN distance: not found), found by repel for the
  // continuous test that follows it on the same lists (detect): valid until the next broad phase.
  std::vector<Closest> round_closest;
  bool round_closest_valid = false;
  std::vector<int> subset;  // the candidates a search tests (subsetOf)

  // A new round's candidates (a broad phase's or a kept list's): what was known of the last is void.
  void renew(bool culls) {
    cull = culls;
    step = nullptr;
    from_skin = false;
    round_closest_valid = false;
  }
  const PairList& vfList() const { return step ? step->vf : vf; }
  const PairList& eeList() const { return step ? step->ee : ee; }
  int count() const { return int(vfList().size() + eeList().size()); }
  // Candidate k's kind and its two elements (vf, then ee).
  std::tuple<Primitive, int, int> candidate(int k) const {
    const auto &v = vfList(), &e = eeList();
    return k < int(v.size()) ? std::tuple{Primitive::PointTriangle, v[k].first, v[k].second}
                             : std::tuple{Primitive::EdgeEdge, e[k - v.size()].first, e[k - v.size()].second};
  }
  PairInfo info(const SurfaceNodes& nodes, int k) const {
    const auto [kind, first, second] = candidate(k);
    return nodes.info(kind, first, second);
  }
  // The stencil's vertices of candidate k (PairInfo's, without the rest).
  std::array<int, 4> pairNodes(const SurfaceNodes& nodes, int k) const {
    const auto [kind, first, second] = candidate(k);
    return nodes.nodes(kind, first, second);
  }
  // The nearest points at the start of candidate k (whose stencil's start points are x), from the step's when known.
  Closest startClosest(int k, Primitive kind, const std::array<Vec3, 4>& x) const {
    if (step) return step->closest[k];
    return nearest(kind, x);
  }
  // With the step's candidates: those of a list (StepCandidates) whose slack is at most 2 drift, ascending; nullptr
  // (every candidate) otherwise.
  const std::vector<int>* subsetOf(const std::vector<std::pair<int, double>>& list) {
    if (!step) return nullptr;
    subset.clear();
    for (const auto& [k, slack] : list)
      if (!(slack > 2 * drift)) subset.push_back(k);
    return &subset;
  }

  // fn(k, info) over every candidate pair k (or those in only, ascending) on threads in fixed chunks; what it returns
  // (an optional) is gathered in pair order. With counted, fn(k, info, count) may also count, each chunk on its own,
  // and *counted is the sum.
  template <class Fn>
  auto gather(const SurfaceNodes& nodes, bool parallel, Fn&& fn, const std::vector<int>* only = nullptr,
              std::size_t* counted = nullptr) const {
    constexpr bool counts = std::is_invocable_v<Fn&, int, const PairInfo&, std::size_t&>;
    using Found = typename std::conditional_t<counts, std::invoke_result<Fn&, int, const PairInfo&, std::size_t&>,
                                              std::invoke_result<Fn&, int, const PairInfo&>>::type::value_type;
    const int n = only ? int(only->size()) : count();
    const int chunk = 1024, chunks = (n + chunk - 1) / chunk;
    std::vector<std::vector<Found>> parts(chunks);
    std::vector<std::size_t> counts_(chunks, 0);
    const auto run = [&](int c) {
      for (int j = c * chunk; j < std::min(n, (c + 1) * chunk); ++j) {
        const int k = only ? (*only)[j] : j;
        if constexpr (counts) {
          if (auto found = fn(k, info(nodes, k), counts_[c])) parts[c].push_back(*found);
        } else if (auto found = fn(k, info(nodes, k))) {
          parts[c].push_back(*found);
        }
      }
    };
    if (parallel && chunks > 1)
      tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& r) {
        for (int c = r.begin(); c != r.end(); ++c) run(c);
      });
    else
      for (int c = 0; c < chunks; ++c) run(c);
    std::vector<Found> out;
    for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
    if (counted) *counted = std::accumulate(counts_.begin(), counts_.end(), std::size_t(0));
    return out;
  }
};

// The pairs of old with neither element marked (first_marked, second_marked) and the fresh ones, merged in order into
// out; per pair of out, appended to from when given, its index in old plus offset (-1: fresh).
inline void mergeUnmarked(const PairList& old, const PairList& fresh, const std::vector<char>& first_marked,
                          const std::vector<char>& second_marked, PairList& out, std::vector<int>* from = nullptr,
                          int offset = 0) {
  out.clear();
  std::size_t j = 0;
  const auto add_fresh = [&] {
    out.push_back(fresh[j++]);
    if (from) from->push_back(-1);
  };
  for (std::size_t i = 0; i < old.size(); ++i) {
    if (first_marked[old[i].first] || second_marked[old[i].second]) continue;
    while (j < fresh.size() && fresh[j] < old[i]) add_fresh();
    out.push_back(old[i]);
    if (from) from->push_back(offset + int(i));
  }
  while (j < fresh.size()) add_fresh();
}

}  // namespace wobble::collision
