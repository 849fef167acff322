// An order for loops over particle pairs (springs, the Jacobian's off-diagonal blocks) that add into both particles
// of each pair, so that they run on threads without locks and give the same bytes whatever the thread count.
// Particles are cut into contiguous blocks at least as long as the longest pair's index span, so a pair joins one
// block or two neighbouring ones. Phase 0 runs each block's own pairs, phase 1 the pairs between blocks 2k and
// 2k + 1, phase 2 those between 2k + 1 and 2k + 2: the tasks of a phase touch disjoint particles, and every
// particle receives its terms in one fixed order. Within a task the pairs are sorted by (b - a, a), which cuts them
// into runs (a0 + k, a0 + offset + k), k = 0 .. length - 1: a lattice body's springs come in runs as long as a row,
// which loops can read and write as contiguous memory (spring_runs.h). Built once per topology.
#pragma once
#include <span>
#include <vector>

#include "sim/solver/parallel.h"

namespace wobble {

// Pairs first .. first + length - 1 (schedule order) are (a + k, a + offset + k), k = 0 .. length - 1.
struct PairRun {
  int first = 0, length = 0, a = 0, offset = 0;
};

// Runs shorter than this are taken a pair at a time by the loops over runs (splitRuns).
inline constexpr int kMinPairRun = 8;

// A task's runs, in schedule order: long(run) for each run of at least kMinPairRun pairs, pairs(begin, end) for each
// stretch of shorter runs between them (a task's runs are consecutive pairs).
template <class LongRun, class Pairs>
void splitRuns(std::span<const PairRun> runs, LongRun&& long_run, Pairs&& pairs) {
  if (runs.empty()) return;
  int pending = runs.front().first;
  for (const PairRun& run : runs) {
    if (run.length < kMinPairRun) continue;
    if (pending < run.first) pairs(pending, run.first);
    long_run(run);
    pending = run.first + run.length;
  }
  const int end = runs.back().first + runs.back().length;
  if (pending < end) pairs(pending, end);
}

class PairSchedule {
 public:
  PairSchedule() = default;
  // a, b: the pairs' particle indices in [0, particles). order() is then the pairs' new order.
  PairSchedule(std::span<const int> a, std::span<const int> b, int particles);

  // order()[k] is the input index of the k-th pair in schedule order; a(), b() are in schedule order.
  const std::vector<int>& order() const { return order_; }
  const std::vector<int>& a() const { return a_; }
  const std::vector<int>& b() const { return b_; }
  int particles() const { return particles_; }
  std::size_t size() const { return a_.size(); }
  // Every run, task by task in schedule order: together they cover each pair once.
  const std::vector<PairRun>& runs() const { return runs_; }

  // fn(begin, end) over ranges of pairs in schedule order, phase by phase, the ranges of a phase on threads
  // when parallel.
  template <class Fn>
  void run(bool parallel, Fn&& fn) const {
    forEachTask(parallel, [&](int t) {
      if (task_begin_[t] < task_begin_[t + 1]) fn(task_begin_[t], task_begin_[t + 1]);
    });
  }
  // The same tasks, each as its runs: fn(std::span<const PairRun>).
  template <class Fn>
  void runByRuns(bool parallel, Fn&& fn) const {
    forEachTask(parallel, [&](int t) {
      const int first = task_runs_[t], last = task_runs_[t + 1];
      if (first < last) fn(std::span<const PairRun>(runs_.data() + first, last - first));
    });
  }
  // runByRuns with the particles: each phase-0 task as block(begin, end, runs), its block of particles [begin, end)
  // (the blocks cover every particle once) and its own pairs; the later phases' tasks as fn(runs). A phase-0 task's
  // pairs touch its block's particles only, so block() may first do per-particle work there (a vector update the
  // pairs then read), fused into the pass instead of a loop and a wait of its own.
  template <class Block, class Fn>
  void runByBlocks(bool parallel, Block&& block, Fn&& fn) const {
    const int blocks = phase_begin_.size() > 1 ? phase_begin_[1] : 0;  // none in a default schedule
    forEachTask(parallel, [&](int t) {
      const int first = task_runs_[t], last = task_runs_[t + 1];
      const std::span<const PairRun> runs(runs_.data() + first, last - first);
      if (t < blocks) block(t * block_, std::min(particles_, (t + 1) * block_), runs);
      else if (first < last) fn(runs);
    });
  }

 private:
  template <class Task>
  void forEachTask(bool parallel, Task&& task) const {
    for (std::size_t p = 0; p + 1 < phase_begin_.size(); ++p) {
      const int first = phase_begin_[p], last = phase_begin_[p + 1];
      if (parallel && last - first > 1)
        tbb::parallel_for(tbb::blocked_range<int>(first, last, 1), [&](const tbb::blocked_range<int>& r) {
          for (int t = r.begin(); t != r.end(); ++t) task(t);
        });
      else
        for (int t = first; t < last; ++t) task(t);
    }
  }

  std::vector<int> order_, a_, b_;
  std::vector<int> task_begin_;   // pair ranges, tasks in phase order
  std::vector<int> phase_begin_;  // task ranges of the three phases
  std::vector<PairRun> runs_;
  std::vector<int> task_runs_;  // run ranges of the tasks
  int particles_ = 0;
  int block_ = 1;  // particles per block (the last may be shorter)
};

}  // namespace wobble
