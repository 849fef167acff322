#include "sim/solver/graph_dissection.h"

#include <algorithm>

namespace wobble {

std::vector<int> dissect(int n, const std::vector<std::pair<int, int>>& edges) {
  std::vector<int> start(n + 1, 0), neighbours(2 * edges.size());
  for (const auto& [i, j] : edges) ++start[i + 1], ++start[j + 1];
  for (int i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const auto& [i, j] : edges) neighbours[fill[i]++] = j, neighbours[fill[j]++] = i;
  std::vector<int> level(n), queue;
  const auto search = [&](int root) {
    std::fill(level.begin(), level.end(), -1);
    queue.assign(1, root);
    level[root] = 0;
    for (std::size_t k = 0; k < queue.size(); ++k)
      for (int e = start[queue[k]]; e < start[queue[k] + 1]; ++e)
        if (level[neighbours[e]] < 0) level[neighbours[e]] = level[queue[k]] + 1, queue.push_back(neighbours[e]);
  };
  std::vector<int> part(n, 1);
  if (n == 0) return part;
  search(0);
  {
    int root = queue.back();  // of the last level, a node of fewest neighbours (a grid's corner rather than a side)
    for (auto it = queue.rbegin(); it != queue.rend() && level[*it] == level[queue.back()]; ++it)
      if (start[*it + 1] - start[*it] < start[root + 1] - start[root]) root = *it;
    search(root);
  }
  std::vector<int> count(level[queue.back()] + 1, 0);
  for (int node : queue) ++count[level[node]];
  // The separator: the smallest level that leaves at least 45% of the graph on either side (the first such one on
  // ties), or the middle level when none does.
  int middle = 0;
  for (int before = 0; middle + 1 < int(count.size()) && 2 * (before + count[middle]) < n; ++middle)
    before += count[middle];
  for (int l = 0, before = 0; l < int(count.size()); before += count[l++])
    if (20 * before >= 9 * n && 20 * (n - before - count[l]) >= 9 * n && count[l] < count[middle]) middle = l;
  for (int node : queue) part[node] = level[node] < middle ? 0 : level[node] == middle ? 2 : 1;
  return part;
}

}  // namespace wobble
