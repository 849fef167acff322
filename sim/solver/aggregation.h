// Aggregation for the implicit solver's coarse level (coarse_correction.h): particles grouped by the springs between
// them, once per topology, so that each group can move as one. Two rounds: each particle whose neighbours are all
// unassigned starts a group with them (greedily, in index order), the rest join the neighbouring group they touch most;
// then those groups are matched in pairs by the same rule on their own graph. On a lattice cloth a group holds about
// 29 particles (348 of them on the 100 x 100 cloth). Deterministic: index order throughout.
#pragma once
#include <vector>

namespace wobble {

// Per particle of n, joined pairwise by springs (a[k], b[k]): its aggregate, numbered 0 .. aggregates - 1.
std::vector<int> aggregateParticles(const std::vector<int>& a, const std::vector<int>& b, int n, int& aggregates);

}  // namespace wobble
