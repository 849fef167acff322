// Convergence orders: the method's theoretical order of global accuracy (docs/numerics.md), and the observed order as
// the least-squares slope of log(error) against log(step). fitOrder returns NaN with fewer than two usable points
// (a point is usable when both values are finite and positive).
#pragma once
#include <string_view>
#include <vector>

namespace wobble {

// The method's order from the method table (sim/integrators/integrator.cpp): explicit-euler, symplectic-euler,
// pc-euler, backward-euler 1; midpoint 2; rk4 4; rk45 5. Throws std::invalid_argument for an unknown name.
int convergenceOrder(std::string_view integrator);

double fitOrder(const std::vector<double>& step, const std::vector<double>& error);

}  // namespace wobble
