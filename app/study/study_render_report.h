// The report of `wobble study render` (study_render.h): from its result alone, the Markdown (slopes, the samples and
// time each variant needs to reach given errors, every point, the variants), the CSV of every point and the
// work-precision diagram (work_precision.h: RMSE against render time, and against samples per pixel).
#pragma once
#include <filesystem>
#include <string>

#include "app/study/gnuplot.h"
#include "app/study/study_render.h"

namespace wobble {

// OUT/render.csv, render.md, render.gp and (through gnuplot) render.png; returns the plot's outcome.
PlotResult writeRenderStudyOutputs(const RenderStudyResult& result, const std::filesystem::path& out,
                                   const std::string& gnuplot = "gnuplot");
std::string renderStudyMarkdown(const RenderStudyResult& result);

}  // namespace wobble
