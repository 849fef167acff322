// The files a work-precision study (`study accuracy`, `study render`) leaves beside its Markdown: NAME.csv, every
// point of the study, and NAME.gp, a gnuplot script of two log-log panels side by side with one curve per integrator
// or variant, rendered (through gnuplot.h) to NAME.png. The studies fill in what differs: the columns, the curves'
// data, the labels and any extra line; the layout, the data blocks and the plot commands are written here once.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "app/study/gnuplot.h"
#include "io/text_table.h"

namespace wobble {

struct WorkPrecisionCurve {
  std::string title;              // integrator or variant
  std::vector<std::string> rows;  // data lines, space-separated columns, without the newline
};

struct WorkPrecisionPanel {
  std::string setup;    // gnuplot lines before its `plot` (axis labels), each ending in a newline
  std::string columns;  // the data columns plotted, "x:y", e.g. "1:3"
  std::string extra;    // appended to its plot command (", f(x) title ..."), or empty
};

struct WorkPrecisionPlot {
  std::string comment;       // what the script draws (its first line, after "# ")
  std::string setup;         // after the shared settings (log-log, grid, key), before the data
  std::string layout_setup;  // after the data, before the panels' layout
  std::string title;         // the layout's title
  std::vector<WorkPrecisionCurve> curves;
  std::array<WorkPrecisionPanel, 2> panels;
};

// The script's text (also what the tests read).
std::string workPrecisionScript(const WorkPrecisionPlot& plot, const std::string& png_name);

// Writes OUT/NAME.csv (the table) and OUT/NAME.gp, then NAME.png through gnuplot; returns the plot's outcome.
// Creates OUT.
PlotResult writeWorkPrecision(const std::filesystem::path& out, const std::string& name, const io::TextTable& csv,
                              const WorkPrecisionPlot& plot, const std::string& gnuplot);

}  // namespace wobble
