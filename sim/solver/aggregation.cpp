#include "sim/solver/aggregation.h"

#include <map>
#include <utility>

namespace wobble {
namespace {

// One round on a graph of n nodes with edges (ea[k], eb[k]): greedy neighbourhoods, or (matching) pairs.
std::vector<int> aggregateGraph(const std::vector<int>& ea, const std::vector<int>& eb, int n, int& aggregates,
                                bool matching) {
  std::vector<int> start(n + 1, 0), neighbours(2 * ea.size());
  for (std::size_t e = 0; e < ea.size(); ++e) ++start[ea[e] + 1], ++start[eb[e] + 1];
  for (int p = 0; p < n; ++p) start[p + 1] += start[p];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (std::size_t e = 0; e < ea.size(); ++e) {
    neighbours[fill[ea[e]]++] = eb[e];
    neighbours[fill[eb[e]]++] = ea[e];
  }
  std::vector<int> aggregate(n, -1);
  aggregates = 0;
  if (matching) {
    for (int p = 0; p < n; ++p) {
      if (aggregate[p] >= 0) continue;
      std::map<int, int> counts;
      for (int k = start[p]; k < start[p + 1]; ++k)
        if (aggregate[neighbours[k]] < 0) ++counts[neighbours[k]];
      int best = -1, most = 0;
      for (const auto& [q, count] : counts)
        if (count > most) best = q, most = count;
      aggregate[p] = aggregates;
      if (best >= 0) aggregate[best] = aggregates;
      ++aggregates;
    }
    return aggregate;
  }
  for (int p = 0; p < n; ++p) {
    if (aggregate[p] >= 0) continue;
    bool free = true;
    for (int k = start[p]; k < start[p + 1] && free; ++k) free = aggregate[neighbours[k]] < 0;
    if (!free) continue;
    aggregate[p] = aggregates;
    for (int k = start[p]; k < start[p + 1]; ++k) aggregate[neighbours[k]] = aggregates;
    ++aggregates;
  }
  std::vector<int> joined(aggregate);
  for (int p = 0; p < n; ++p) {
    if (aggregate[p] >= 0) continue;
    std::map<int, int> counts;
    for (int k = start[p]; k < start[p + 1]; ++k)
      if (aggregate[neighbours[k]] >= 0) ++counts[aggregate[neighbours[k]]];
    int best = -1, most = 0;
    for (const auto& [agg, count] : counts)
      if (count > most) best = agg, most = count;
    joined[p] = best >= 0 ? best : aggregates++;
  }
  return joined;
}

}  // namespace

std::vector<int> aggregateParticles(const std::vector<int>& a, const std::vector<int>& b, int n, int& aggregates) {
  std::vector<int> ea(a), eb(b);
  std::vector<int> composed(n);
  for (int p = 0; p < n; ++p) composed[p] = p;
  int nodes = n;
  aggregates = n;
  for (int round = 0; round < 2; ++round) {
    const std::vector<int> agg = aggregateGraph(ea, eb, nodes, aggregates, round > 0);
    for (int p = 0; p < n; ++p) composed[p] = agg[composed[p]];
    std::vector<int> na, nb;
    for (std::size_t e = 0; e < ea.size(); ++e)
      if (agg[ea[e]] != agg[eb[e]]) na.push_back(agg[ea[e]]), nb.push_back(agg[eb[e]]);
    ea = std::move(na), eb = std::move(nb);
    nodes = aggregates;
  }
  return composed;
}

}  // namespace wobble
