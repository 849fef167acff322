#include "sim/contact/broad_phase/broad_phase.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>

#include "sim/contact/release.h"
#include "sim/solver/parallel.h"

namespace wobble::collision {
namespace {

constexpr std::int64_t kMaxCellsPerBox = 512;  // a larger box (a fast element) goes to the list every query sees

class HashGrid {
 public:
  HashGrid(const std::vector<Box>& targets, bool parallel) {
    const int n = static_cast<int>(targets.size());
    double extent = 0;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    for (const Box& b : targets) {
      extent += (b.hi - b.lo).maxCoeff();
      lo = lo.cwiseMin(b.lo);
    }
    const double cell = n > 0 && extent > 0 ? extent / n : 1.0;
    inverse_cell_ = 1 / cell;
    origin_ = n > 0 ? lo : Vec3::Zero();
    std::uint64_t size = 1024;
    while (size < 2 * std::uint64_t(n)) size *= 2;
    mask_ = size - 1;
    start_.assign(size + 1, 0);
    // Each target's buckets, one per cell of its box, found on threads (the floors and hashes are the work) into one
    // list in target order; then a counting sort of that list by bucket on one thread, in target order: the same grid
    // whatever the threads, with the costly part of a build (once all of it serial at every broad phase) shared.
    std::vector<int> first(n + 1, 0);  // target t's buckets: keys[first[t], first[t + 1])
    std::vector<Eigen::Array3i> low(n), high(n);
    forEachChunk(n, parallel, [&](int begin, int end) {
      for (int t = begin; t < end; ++t)
        first[t + 1] = cellRange(targets[t], low[t], high[t]) ? (high[t] - low[t] + 1).prod() : -1;
    });
    for (int t = 0; t < n; ++t) {
      if (first[t + 1] < 0) {
        oversized_.push_back(t);
        first[t + 1] = 0;
      }
      first[t + 1] += first[t];
    }
    std::vector<std::uint32_t> keys(first[n]);
    forEachChunk(n, parallel, [&](int begin, int end) {
      for (int t = begin; t < end; ++t) {
        if (first[t + 1] == first[t]) continue;  // oversized (a box in the grid has a cell at least)
        int j = first[t];
        forCells(low[t], high[t], [&](std::uint64_t k) { keys[j++] = std::uint32_t(k); });
      }
    });
    for (const std::uint32_t k : keys) ++start_[k + 1];
    for (std::uint64_t k = 0; k < size; ++k) start_[k + 1] += start_[k];
    entries_.resize(start_[size]);
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (int t = 0; t < n; ++t)
      for (int j = first[t]; j < first[t + 1]; ++j) entries_[fill[keys[j]]++] = t;
  }

  // fn(t) for every target in the buckets of the box's cells (duplicates and false overlaps included).
  template <class Fn>
  void forCandidates(const Box& box, Fn&& fn) const {
    for (const int t : oversized_) fn(t);
    Eigen::Array3i a, b;
    const auto bucket = [&](std::uint64_t k) {
      for (int e = start_[k]; e < start_[k + 1]; ++e) fn(entries_[e]);
    };
    if (!cellRange(box, a, b)) {  // a huge query: every target
      for (std::uint64_t k = 0; k + 1 < start_.size(); ++k) bucket(k);
      return;
    }
    forCells(a, b, bucket);
  }

 private:
  template <class Fn>
  void forCells(const Eigen::Array3i& a, const Eigen::Array3i& b, Fn&& fn) const {
    for (int i = a.x(); i <= b.x(); ++i)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int k = a.z(); k <= b.z(); ++k)
          fn((std::uint64_t(i) * 73856093u ^ std::uint64_t(j) * 19349663u ^ std::uint64_t(k) * 83492791u) & mask_);
  }

  bool cellRange(const Box& box, Eigen::Array3i& a, Eigen::Array3i& b) const {
    const Eigen::Array3d lo = ((box.lo - origin_) * inverse_cell_).array().floor();
    const Eigen::Array3d hi = ((box.hi - origin_) * inverse_cell_).array().floor();
    const Eigen::Array3d span = hi - lo + 1;
    if (!(span.prod() <= double(kMaxCellsPerBox)) || !(lo.abs().maxCoeff() < 1e9) || !(hi.abs().maxCoeff() < 1e9))
      return false;
    a = lo.cast<int>();
    b = hi.cast<int>();
    return true;
  }

  double inverse_cell_ = 1;
  Vec3 origin_ = Vec3::Zero();
  std::uint64_t mask_ = 0;
  std::vector<int> start_, entries_;
  std::vector<int> oversized_;
};

// Every (q, t) with q a query that wanted(q) and t a target of the grid (its index through target_index when that
// is not empty) whose boxes overlap and accepted(q, t) holds, appended by ascending q, then t. above: only t > q (one
// list on both sides, each pair once), tested before the rest.
// Returns false (out incomplete) once more than limit pairs are found.
template <class Wanted, class Accepted>
bool lookUp(const HashGrid& grid, const std::vector<Box>& queries, const std::vector<Box>& targets,
            const std::vector<int>& target_index, bool above, bool parallel, Wanted&& wanted, Accepted&& accepted,
            std::vector<std::pair<int, int>>& out, std::size_t limit) {
  static std::atomic<std::uint64_t> calls{0};
  const std::uint64_t call = ++calls;
  const int n = static_cast<int>(queries.size()), chunk = particleChunk(n), chunks = (n + chunk - 1) / chunk;
  std::vector<std::vector<std::pair<int, int>>> parts(chunks);
  std::atomic<std::size_t> found{out.size()};
  forEachChunk(n, parallel, [&](int begin, int end) {
    // A target met again within one query (it spans several of the query's cells) is skipped by its stamp: the
    // call's number and the query's index, unique over the process.
    thread_local std::vector<std::uint64_t> stamp;
    if (stamp.size() < targets.size()) stamp.resize(targets.size(), 0);
    auto& part = parts[begin / chunk];
    for (int q = begin; q < end; ++q) {
      if (!wanted(q)) continue;
      const std::size_t first = part.size();
      const std::uint64_t mark = (call << 32) | std::uint64_t(q);
      const Box& box = queries[q];
      grid.forCandidates(box, [&](int t) {
        if (!target_index.empty()) t = target_index[t];
        if (above && t <= q) return;
        if (stamp[t] == mark) return;
        stamp[t] = mark;
        if (box.overlaps(targets[t]) && accepted(q, t)) part.emplace_back(q, t);
      });
      std::sort(part.begin() + first, part.end());  // ascending t: the order of the grid's buckets is not
      if ((found += part.size() - first) > limit) return;
    }
  });
  if (found > limit) return false;
  // out at its final size at once, each part let go as soon as it is in: a list grown by doubling beside parts grown
  // so would hold up to four times its bytes at a landing.
  out.reserve(found);
  for (auto& part : parts) {
    out.insert(out.end(), part.begin(), part.end());
    release(part);
  }
  return true;
}

}  // namespace

bool overlappingPairs(const std::vector<Box>& queries, const std::vector<Box>& targets, bool same, bool parallel,
                      const std::function<bool(int, int)>& keep, std::vector<std::pair<int, int>>& out,
                      std::size_t limit) {
  out.clear();
  if (queries.empty() || targets.empty()) return true;
  return lookUp(
      HashGrid(targets, parallel), queries, targets, {}, same, parallel, [](int) { return true; },
      [&](int q, int t) { return keep(q, t); }, out, limit);
}

bool overlappingMarkedPairs(const std::vector<Box>& queries, const std::vector<Box>& targets, bool same, bool parallel,
                            const std::vector<char>& query_marked, const std::vector<char>& target_marked,
                            const std::function<bool(int, int)>& keep, std::vector<std::pair<int, int>>& out,
                            std::size_t limit) {
  out.clear();
  if (queries.empty() || targets.empty()) return true;
  // Two disjoint lists, each ascending, merged: the marked queries against every target, and every other query against
  // the marked targets (a grid of those alone). With one list on both sides (same) both take only t > q: a pair (a < b)
  // comes from a when a is marked, else from b's mark through the second list, each once.
  std::vector<std::pair<int, int>> marked_queries, other_queries;
  if (!lookUp(
          HashGrid(targets, parallel), queries, targets, {}, same, parallel,
          [&](int q) { return query_marked[q] != 0; }, [&](int q, int t) { return keep(q, t); }, marked_queries, limit))
    return false;
  std::vector<Box> marked;
  std::vector<int> index;
  for (std::size_t t = 0; t < targets.size(); ++t)
    if (target_marked[t]) {
      marked.push_back(targets[t]);
      index.push_back(int(t));
    }
  if (!marked.empty() && !lookUp(
                             HashGrid(marked, parallel), queries, targets, index, same, parallel,
                             [&](int q) { return query_marked[q] == 0; }, [&](int q, int t) { return keep(q, t); },
                             other_queries, limit - std::min(limit, marked_queries.size())))
    return false;
  out.reserve(marked_queries.size() + other_queries.size());
  std::merge(marked_queries.begin(), marked_queries.end(), other_queries.begin(), other_queries.end(),
             std::back_inserter(out));
  return true;
}

}  // namespace wobble::collision
