// The report of `wobble study accuracy` (study_accuracy.h): from its result alone, the Markdown (fitted orders, the
// fastest integrator per error, every point, what was left out), the CSV of every point and the work-precision
// diagram (work_precision.h: error against run time, one curve per integrator).
#pragma once
#include <filesystem>
#include <string>

#include "app/study/gnuplot.h"
#include "app/study/study_accuracy.h"

namespace wobble {

// Writes OUT/accuracy.csv, OUT/accuracy.md, OUT/accuracy.gp and (through gnuplot) OUT/accuracy.png; returns the
// plot's outcome. Creates OUT.
PlotResult writeAccuracyOutputs(const AccuracyResult& result, const std::filesystem::path& out,
                                const std::string& gnuplot = "gnuplot");

// The Markdown report alone (tables, fitted orders, notes).
std::string accuracyMarkdown(const AccuracyResult& result);

}  // namespace wobble
