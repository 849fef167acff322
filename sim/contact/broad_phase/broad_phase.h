// Broad phase: which boxes of one list may overlap which boxes of another, with a uniform spatial hash (Teschner et
// al. 2003, "Optimized spatial hashing for collision detection of deformable objects"). The targets are counted into
// hash buckets of a grid whose cell is their mean extent; each query visits the buckets of its cells. A hash rather
// than a refitted BVH or Embree's rtcCollide: sim/ may not include render/ (where Embree is wrapped), the hash is
// rebuilt from scratch each time (the boxes' cells found on threads, then a counting sort), with no refit quality to
// lose as a cloth crumples, and its output is sorted, hence the same whatever the thread count
// (docs/body-contact.md).
#pragma once
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "sim/types.h"

namespace wobble::collision {

struct Box {
  Vec3 lo, hi;
  bool overlaps(const Box& o) const { return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all(); }
};

// Every pair (query q, target t) whose boxes overlap and for which keep(q, t) holds, ascending by (q, t). With the
// same list on both sides pass same = true: each unordered pair once, q < t. Runs queries in fixed chunks on threads
// when parallel; the result does not depend on it. Returns false, out incomplete, when there would be more than limit
// pairs (boxes so large that the list would take more memory than a step may: the caller stops).
bool overlappingPairs(const std::vector<Box>& queries, const std::vector<Box>& targets, bool same, bool parallel,
                      const std::function<bool(int, int)>& keep, std::vector<std::pair<int, int>>& out,
                      std::size_t limit = SIZE_MAX);

// The pairs of overlappingPairs that have a marked query or a marked target (marks: one char per box), in the same
// order: for the later rounds of a step, where only pairs with an element that moved can newly collide. Marked
// queries look up every target; every other query looks up the marked targets only. Returns false as above.
bool overlappingMarkedPairs(const std::vector<Box>& queries, const std::vector<Box>& targets, bool same, bool parallel,
                            const std::vector<char>& query_marked, const std::vector<char>& target_marked,
                            const std::function<bool(int, int)>& keep, std::vector<std::pair<int, int>>& out,
                            std::size_t limit = SIZE_MAX);

}  // namespace wobble::collision
