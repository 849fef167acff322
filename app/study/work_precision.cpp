#include "app/study/work_precision.h"

#include <sstream>

#include "io/text_file.h"

namespace fs = std::filesystem;

namespace wobble {

std::string workPrecisionScript(const WorkPrecisionPlot& plot, const std::string& png_name) {
  std::ostringstream gp;
  gp << "# " << plot.comment << "\n"
     << "if (!exists(\"out\")) out = '" << png_name << "'\n"
     << "set terminal pngcairo size 1400,600 noenhanced\nset output out\n"
     << "set logscale xy\nset grid\nset key top right\n"
     << plot.setup;
  for (std::size_t i = 0; i < plot.curves.size(); ++i) {
    gp << "$d" << i << " << EOD\n";
    for (const std::string& row : plot.curves[i].rows) gp << row << "\n";
    gp << "EOD\n";
  }
  gp << plot.layout_setup << "set multiplot layout 1,2 title " << gnuplotQuote(plot.title) << "\n";
  for (const WorkPrecisionPanel& panel : plot.panels) {
    gp << panel.setup << "plot ";
    for (std::size_t i = 0; i < plot.curves.size(); ++i)
      gp << (i ? ", " : "") << "$d" << i << " using " << panel.columns << " with linespoints lw 2 pt 7 title "
         << gnuplotQuote(plot.curves[i].title);
    gp << panel.extra << "\n";
  }
  gp << "unset multiplot\n";
  return gp.str();
}

PlotResult writeWorkPrecision(const fs::path& out, const std::string& name, const io::TextTable& csv,
                              const WorkPrecisionPlot& plot, const std::string& gnuplot) {
  fs::create_directories(out);
  io::writeTextFile(out / (name + ".csv"), csv.csv());
  const fs::path script = out / (name + ".gp"), png = out / (name + ".png");
  io::writeTextFile(script, workPrecisionScript(plot, png.filename().string()));
  return runGnuplot(script, png, gnuplot);
}

}  // namespace wobble
