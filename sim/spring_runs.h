// The spring force loop over runs of springs (pair_schedule.h): a run's endpoints, velocities and forces are
// contiguous memory, so it is read without index gathers and its forces, computed a chunk at a time into a small
// buffer, are added to f[a ..] and subtracted from f[a + offset ..] in two plain loops the compiler vectorises. Short
// runs (kMinPairRun) go through the scalar loop (springs.h). The same forces to round-off, summed in another fixed order.
#pragma once
#include <span>

#include "sim/pair_schedule.h"
#include "sim/springs.h"

namespace wobble {

// f += the forces of the springs in runs (the springs in schedule order: run.first indexes s).
void addSpringForces(const Springs& s, std::span<const PairRun> runs, const VecX& x, const VecX& v, VecX& f);

}  // namespace wobble
