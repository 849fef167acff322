// The spring force loop over runs of springs (pair_schedule.h): a run's endpoints, velocities and forces are
// contiguous memory, so it is read without index gathers and its forces, computed a chunk at a time into a small
// buffer, are added to f[a ..] and subtracted from f[a + offset ..] in two plain loops the compiler vectorises. Short
// runs (kMinPairRun) go through the scalar loop (springs.h). The same forces to round-off, summed in another fixed
// order. The implicit solver's spring Jacobian blocks are filled over the same runs (force_jacobian.h has the
// formulas).
#pragma once
#include <span>

#include "sim/solver/pair_schedule.h"
#include "sim/springs.h"
#include "sim/solver/sym3.h"

namespace wobble {

// f += the forces of the springs in runs (the springs in schedule order: run.first indexes s).
void addSpringForces(const Springs& s, std::span<const PairRun> runs, const VecX& x, const VecX& v, VecX& f);

// The springs' Jacobian blocks of the runs (fillSpringBlocks of force_jacobian.h, the same values to round-off).
void fillSpringBlocks(const Springs& s, std::span<const PairRun> runs, const VecX& x, double cx, double cv,
                      PairBlockColumns blocks, const VecX* w, VecX* kw);

}  // namespace wobble
