#include "sim/solver/pair_schedule.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace wobble {
PairSchedule::PairSchedule(std::span<const int> a, std::span<const int> b, int particles) : particles_(particles) {
  if (a.size() != b.size()) throw std::invalid_argument("PairSchedule: a and b differ in length");
  int span = 1;
  for (std::size_t e = 0; e < a.size(); ++e) span = std::max(span, std::abs(a[e] - b[e]));
  const int block = std::max(particleChunk(particles), span);
  block_ = block;
  const int blocks = std::max(1, (particles + block - 1) / block);
  // Task of each pair: its block's own pairs (phase 0, tasks 0..blocks-1), or the pairs between blocks k and k + 1
  // (tasks blocks + k). Phases 1 and 2 take the even and the odd k.
  const auto taskOf = [&](std::size_t e) {
    const int ka = a[e] / block, kb = b[e] / block;
    return ka == kb ? ka : blocks + std::min(ka, kb);
  };
  std::vector<int> rank(2 * blocks);  // task -> its place in run order
  int next = 0;
  for (int k = 0; k < blocks; ++k) rank[k] = next++;
  for (int k = 0; k < blocks; k += 2) rank[blocks + k] = next++;
  const int odd_first = next;
  for (int k = 1; k < blocks; k += 2) rank[blocks + k] = next++;
  // Counting sort by task rank; stable, so each task keeps the input order.
  std::vector<int> count(2 * blocks + 1, 0);
  for (std::size_t e = 0; e < a.size(); ++e) ++count[rank[taskOf(e)] + 1];
  for (std::size_t t = 1; t < count.size(); ++t) count[t] += count[t - 1];
  task_begin_.assign(count.begin(), count.end());
  order_.resize(a.size());
  for (std::size_t e = 0; e < a.size(); ++e) order_[count[rank[taskOf(e)]]++] = static_cast<int>(e);
  // Within each task, by (b - a, a): the same particles, in runs. Stable, so equal pairs keep the input order.
  for (std::size_t t = 0; t + 1 < task_begin_.size(); ++t)
    std::stable_sort(order_.begin() + task_begin_[t], order_.begin() + task_begin_[t + 1], [&](int i, int j) {
      const long long oi = static_cast<long long>(b[i]) - a[i], oj = static_cast<long long>(b[j]) - a[j];
      return oi != oj ? oi < oj : a[i] < a[j];
    });
  a_.resize(a.size());
  b_.resize(a.size());
  for (std::size_t k = 0; k < order_.size(); ++k) {
    a_[k] = a[order_[k]];
    b_[k] = b[order_[k]];
  }
  phase_begin_ = {0, blocks, odd_first, 2 * blocks};
  // Runs: maximal stretches of a task whose pairs step both endpoints by one.
  task_runs_.assign(1, 0);
  for (std::size_t t = 0; t + 1 < task_begin_.size(); ++t) {
    for (int e = task_begin_[t]; e < task_begin_[t + 1]; ++e) {
      PairRun* last = runs_.empty() || task_runs_.back() == static_cast<int>(runs_.size()) ? nullptr : &runs_.back();
      if (last && a_[e] == last->a + last->length && b_[e] == last->a + last->offset + last->length) ++last->length;
      else runs_.push_back({e, 1, a_[e], b_[e] - a_[e]});
    }
    task_runs_.push_back(static_cast<int>(runs_.size()));
  }
}

}  // namespace wobble
