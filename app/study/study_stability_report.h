// The report of `wobble study stability` (study_stability.h): from its result alone, the Markdown (the users' cases,
// theory's limits, the measured boundary against theory, a map per integrator), the CSV of every cell and per
// integrator a gnuplot map of the cells with theory's boundary.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "app/study/gnuplot.h"
#include "app/study/study_stability.h"

namespace wobble {

std::string stabilityMarkdown(const StabilityResult& result);

// OUT/stability.csv, OUT/stability.md, and per integrator OUT/stability-<name>.gp and .png. Returns each plot's
// outcome. Creates OUT.
std::vector<PlotResult> writeStabilityOutputs(const StabilityResult& result, const std::filesystem::path& out,
                                              const std::string& gnuplot = "gnuplot");

}  // namespace wobble
