// Loops over particles on TBB threads whose results do not depend on the thread count: work is cut into fixed
// chunks of particles (never into "one piece per thread"), and sums are taken per chunk, then over the chunks in
// order. Small systems run the same chunks serially: below the threshold threads cost more than they give.
#pragma once
#include <algorithm>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <Eigen/Core>

namespace wobble {

// Particles per chunk of the particle loops and of the pair blocks in pair_schedule.h, for a system of n particles:
// about n / 16 (so two threads get equal shares of chunks within 1/16), a multiple of 64, between 512 and 2048
// (larger chunks cost less to schedule; measured: docs/performance.md, "Where threads start to pay"). It depends on n
// only, never on the thread count, so the chunks and their sums are the same whatever the threads.
constexpr int particleChunk(int n) { return std::clamp((n / 16 + 63) / 64 * 64, 512, 2048); }

// Systems with fewer particles than this step on one thread (measured: docs/performance.md, "Where threads start to
// pay"). Tests lower it to 0 to run small systems on threads; results are the same bytes either way.
int parallelThreshold();
void setParallelThreshold(int particles);
inline bool runsInParallel(int particles) { return particles >= parallelThreshold(); }

// fn(begin, end) over [0, n) in chunks of particleChunk(n), on threads when parallel.
template <class Fn>
void forEachChunk(int n, bool parallel, Fn&& fn) {
  const int chunk = particleChunk(n), chunks = (n + chunk - 1) / chunk;
  const auto run = [&](int c) { fn(c * chunk, std::min(n, (c + 1) * chunk)); };
  if (parallel && chunks > 1)
    tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& r) {
      for (int c = r.begin(); c != r.end(); ++c) run(c);
    });
  else
    for (int c = 0; c < chunks; ++c) run(c);
}

// fn(begin, size) over the element ranges of a flat vector of size values, in chunks of 3 particleChunk, on threads
// when the vector is a large system's state (3 values a particle, runsInParallel). For elementwise work, such as an
// integrator's x += h v: each element sees the same operations whatever the chunk, so the bytes do not change.
template <class Fn>
void forEachSegment(Eigen::Index size, Fn&& fn) {
  // The particle chunks of forEachChunk, as element ranges (a state that is not 3 values a particle ends in a part).
  forEachChunk(int((size + 2) / 3), runsInParallel(int(size / 3)), [&](int begin, int end) {
    const Eigen::Index first = 3 * Eigen::Index(begin);
    fn(first, std::min(3 * Eigen::Index(end), size) - first);
  });
}

// The sum of fn(begin, end) over the chunks of [0, n), added in chunk order; T is double or a fixed-size Eigen
// vector (several sums in one pass). partials is scratch, kept between calls so that a step allocates nothing.
template <class T, class Fn>
T sumOverChunks(int n, bool parallel, std::vector<T>& partials, Fn&& fn) {
  const int chunk = particleChunk(n);
  partials.resize((n + chunk - 1) / chunk);
  forEachChunk(n, parallel, [&](int begin, int end) { partials[begin / chunk] = fn(begin, end); });
  if (partials.empty()) return fn(0, 0);  // no particles: the empty sum, of the right type
  T sum = partials[0];
  for (std::size_t c = 1; c < partials.size(); ++c) sum += partials[c];
  return sum;
}

// first() and second() at the same time when parallel, one after the other otherwise. They must not touch the same
// data, so their results do not depend on which runs where.
template <class First, class Second>
void runBoth(bool parallel, First&& first, Second&& second) {
  if (parallel) {
    tbb::parallel_invoke(first, second);
  } else {
    first();
    second();
  }
}

}  // namespace wobble
