// One level of nested dissection of a graph: two parts with no edge between them and a separator between them, for
// a sparse factorization whose two parts' columns can then be eliminated and solved independently (the coarse level's
// LDLT, coarse_correction.h). Breadth-first levels from a far node (of the nodes farthest from node 0, one with the
// fewest neighbours: a grid's corner rather than the middle of a side, whose levels would bend around it): an edge
// joins nodes of one level or of neighbouring levels, so the levels before a separator level and those after it share
// no edge. The separator is the smallest level that leaves at least 45% of the nodes on either side (the first such
// on ties), else the middle level. Nodes the search does not reach (other components) go to part 1.
#pragma once
#include <utility>
#include <vector>

namespace wobble {

// Per node of a graph of n nodes with the given undirected edges (i, j): 0 or 1 (its part) or 2 (the separator).
std::vector<int> dissect(int n, const std::vector<std::pair<int, int>>& edges);

}  // namespace wobble
