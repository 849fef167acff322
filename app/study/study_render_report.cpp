#include "app/study/study_render_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "app/study/study_report.h"
#include "app/study/work_precision.h"
#include "io/text_file.h"
#include "io/text_table.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

std::string pointLabel(const RenderPoint& p) {
  return p.threshold > 0 ? "threshold " + io::formatNumber(p.threshold, 3) : std::to_string(p.spp) + " spp";
}

// The variants the result holds, in the order of their first point.
std::vector<std::string> variantsIn(const RenderStudyResult& r) {
  std::vector<std::string> names;
  for (const RenderPoint& p : r.points)
    if (std::find(names.begin(), names.end(), p.variant) == names.end()) names.push_back(p.variant);
  return names;
}

}  // namespace

std::string renderStudyMarkdown(const RenderStudyResult& r) {
  std::ostringstream md;
  md << "# Render study: " << r.scene_name << ", frame " << r.frame << "\n\n";
  md << "Scene `" << r.scene_file.string() << "`, " << r.width << " x " << r.height << ", " << r.bounces
     << " bounces. Machine: " << machineDescription() << ".\n\n";
  md << "- Reference: " << r.reference_spp << " spp (Sobol, two halves with independent seeds), "
     << (r.reference_cached ? "read from the cache" : "rendered in " + io::formatNumber(r.reference_seconds, 3) + " s")
     << "; its own RMSE is about " << io::formatNumber(r.reference_rmse, 3)
     << " (half the RMSE between its halves): errors below twice that are left out of the slopes.\n"
     << "- RMSE: of display values (tone-mapped, sRGB-encoded, 0..1, as in the PNG) over all pixels and channels; "
        "relMSE: (x - ref)^2 / (ref^2 + 0.01) of linear colour. Worst tile: the 32 x 32 tile with the largest error.\n"
     << "- Time: wall time of rendering plus denoising on all cores (minimum over the repeats).\n\n";

  md << "## Convergence: slope of log RMSE against log samples per pixel\n\n"
        "Plain Monte Carlo converges as spp^-0.5; a steeper (more negative) slope means error falls faster than "
        "1/sqrt(spp). Denoised variants are flat by design: most of their error is the filter's bias.\n\n";
  io::TextTable slopes{{"variant", "slope", "points in fit"}};
  for (const RenderVariantFit& f : r.fits)
    slopes.add({f.variant, std::isnan(f.slope) ? "n/a" : io::formatNumber(f.slope, 3), std::to_string(f.points)});
  md << slopes.markdown() << "\n";

  md << "## Samples per pixel and time to reach an error\n\n"
        "Interpolated (log-log) between the two sweep points around each target RMSE; \"-\" where the sweep never "
        "reached it.\n\n";
  const std::vector<double> targets = {0.05, 0.02, 0.01, 0.005, 0.002, 0.001};
  std::vector<std::string> header = {"variant"};
  for (double t : targets) header.push_back("RMSE " + io::formatNumber(t) + ": spp / s");
  io::TextTable reach{header};
  const std::vector<std::string> names = variantsIn(r);
  for (const std::string& name : names) {
    std::vector<const RenderPoint*> curve;
    for (const RenderPoint& p : r.points)
      if (p.variant == name) curve.push_back(&p);
    std::sort(curve.begin(), curve.end(), [](auto* a, auto* b) { return a->mean_spp < b->mean_spp; });
    std::vector<std::string> row = {name};
    for (double target : targets) {
      std::string cell = "-";
      for (std::size_t i = 0; i < curve.size(); ++i) {
        if (curve[i]->rmse > target) continue;
        if (i == 0) {
          cell = "<= " + io::formatNumber(curve[0]->mean_spp, 3) + " / " + io::formatNumber(curve[0]->seconds, 3);
        } else {
          const RenderPoint &a = *curve[i - 1], &b = *curve[i];
          const double f = std::log(target / a.rmse) / std::log(b.rmse / a.rmse);
          const auto lerp = [&](double x, double y) { return std::exp(std::log(x) + f * (std::log(y) - std::log(x))); };
          cell = io::formatNumber(lerp(a.mean_spp, b.mean_spp), 3) + " / " +
                 io::formatNumber(lerp(a.seconds, b.seconds), 3);
        }
        break;
      }
      row.push_back(cell);
    }
    reach.add(row);
  }
  md << reach.markdown() << "\n";

  md << "## Every point\n\n";
  io::TextTable all{{"variant", "setting", "mean spp", "RMSE", "worst tile RMSE", "relMSE", "worst tile relMSE",
                     "time (s)", "of which denoising (s)"}};
  for (const RenderPoint& p : r.points)
    all.add({p.variant, pointLabel(p), io::formatNumber(p.mean_spp, 4), io::formatNumber(p.rmse, 3),
             io::formatNumber(p.worst_tile_rmse, 3), io::formatNumber(p.relmse, 3),
             io::formatNumber(p.worst_tile_relmse, 3), io::formatNumber(p.seconds, 3),
             io::formatNumber(p.denoise_seconds, 3)});
  md << all.markdown() << "\n";
  md << "## Variants\n\n";
  for (const RenderVariant& v : renderStudyVariants())
    if (std::find(names.begin(), names.end(), v.name) != names.end())
      md << "- `" << v.name << "`: " << v.description << "\n";
  return md.str();
}

PlotResult writeRenderStudyOutputs(const RenderStudyResult& r, const fs::path& out, const std::string& gnuplot) {
  io::TextTable csv{{"scene", "frame", "width", "height", "variant", "spp", "threshold", "mean_spp", "rmse", "relmse",
                     "worst_tile_rmse", "worst_tile_relmse", "seconds", "denoise_seconds", "rays_per_sample",
                     "reference_rmse"}};
  for (const RenderPoint& p : r.points)
    csv.add({r.scene_name, std::to_string(r.frame), std::to_string(r.width), std::to_string(r.height), p.variant,
             std::to_string(p.spp), io::formatNumber(p.threshold, 4), io::formatNumber(p.mean_spp, 6),
             io::formatNumber(p.rmse, 6), io::formatNumber(p.relmse, 6), io::formatNumber(p.worst_tile_rmse, 6),
             io::formatNumber(p.worst_tile_relmse, 6), io::formatNumber(p.seconds, 6),
             io::formatNumber(p.denoise_seconds, 6), io::formatNumber(p.rays_per_sample, 4),
             io::formatNumber(r.reference_rmse, 6)});

  WorkPrecisionPlot plot;
  plot.comment =
      "Work-precision diagram of the renderer on " + r.scene_name + ": gnuplot render.gp (writes render.png)";
  plot.setup = "set format x '%g'\n";
  for (const std::string& name : variantsIn(r)) {
    WorkPrecisionCurve& curve = plot.curves.emplace_back();
    curve.title = name;
    for (const RenderPoint& p : r.points)
      if (p.variant == name)
        curve.rows.push_back(io::formatNumber(p.rmse, 8) + " " + io::formatNumber(p.seconds, 6) + " " +
                             io::formatNumber(p.mean_spp, 6));
  }
  plot.title = "wobble study render: " + r.scene_name + " frame " + std::to_string(r.frame) + ", " +
               std::to_string(r.width) + "x" + std::to_string(r.height);
  plot.panels[0] = {"set xlabel 'RMSE (display values)'\nset ylabel 'render time (s)'\n", "1:2", ""};
  plot.panels[1] = {"set xlabel 'samples per pixel (mean)'\nset ylabel 'RMSE (display values)'\n", "3:1",
                    ", " + io::formatNumber(r.points.empty() ? 0.1 : r.points.front().rmse, 6) +
                        " / sqrt(x) dt 2 lc 'grey' title '1/sqrt(spp)'"};
  fs::create_directories(out);
  io::writeTextFile(out / "render.md", renderStudyMarkdown(r));
  return writeWorkPrecision(out, "render", csv, plot, gnuplot);
}

}  // namespace wobble
