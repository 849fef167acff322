#include "app/study/study_accuracy_report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "app/study/study_report.h"
#include "app/study/work_precision.h"
#include "io/text_file.h"
#include "io/text_table.h"
#include "sim/integrators/integrator.h"

namespace fs = std::filesystem;

namespace wobble {

std::string accuracyMarkdown(const AccuracyResult& r) {
  std::ostringstream md;
  md << "# Accuracy study: " << r.scene_name << "\n\n";
  md << "Scene `" << r.scene_file.string() << "`, simulated time T = " << io::formatNumber(r.duration) << " s, "
     << r.moving_particles << " moving particles of " << r.particles << ". Machine: " << machineDescription()
     << ".\n\n";
  if (r.has_colliders)
    md << "**This scene has colliders: the fitted orders below are not meaningful.** Contact forces switch on and off "
          "and collisions are resolved at step ends (static friction even depends on the step size), so the "
          "trajectory is not a smooth function of time and no method keeps its textbook order; expect about 1 or "
          "less for all of them. Read the errors and run times, not the slopes. rk45 may take at most "
       << kAccuracyContactSubsteps
       << " substeps per scene step here (it crawls through contact switches at tight "
          "tolerances); runs that need more are left out.\n\n";
  else
    md << "The scene has no colliders: the motion is smooth, so the fitted orders should approach the theoretical "
          "ones where the errors are in the asymptotic range.\n\n";
  md << "- Reference: " << r.reference << " (run time " << io::formatNumber(r.reference_seconds, 3)
     << " s, estimated error " << io::formatNumber(r.reference_error, 3)
     << " m; errors below 10x that are left out of the fits).\n"
     << "- Errors are of particle positions against the reference: final = max over moving particles at T; RMS = "
        "over every sample time and moving particle (metres).\n"
     << "- Fixed-step methods use dt = T/2^k; rk45 uses rtol = atol = 10^-j and its order is fitted against its mean "
        "accepted substep.\n"
     << "- Run time: minimum of several runs after a warm-up, wall clock, one thread.\n\n";

  md << "## Fitted convergence order (slope of log error against log dt)\n\n";
  io::TextTable fits{{"integrator", "theory", "fitted (final error)", "fitted (RMS error)", "points in fit"}};
  for (const AccuracyFit& f : r.fits)
    fits.add({f.integrator, std::to_string(f.expected),
              std::isnan(f.order_final) ? "n/a" : io::formatNumber(f.order_final, 3),
              std::isnan(f.order_rms) ? "n/a" : io::formatNumber(f.order_rms, 3), std::to_string(f.points)});
  md << fits.markdown() << "\n";

  md << "## Fastest integrator to reach a final error\n\n";
  io::TextTable fastest{{"final error at most (m)", "fastest integrator", "its setting", "run time (s)", "runner-up"}};
  for (double target : {1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8}) {
    std::map<std::string, const AccuracyPoint*> best;  // per integrator
    for (const AccuracyPoint& p : r.points)
      if (!p.diverged && p.final_error <= target && (!best[p.integrator] || p.seconds < best[p.integrator]->seconds))
        best[p.integrator] = &p;
    std::vector<const AccuracyPoint*> order;
    for (const auto& [name, p] : best)
      if (p) order.push_back(p);
    std::sort(order.begin(), order.end(), [](auto* a, auto* b) { return a->seconds < b->seconds; });
    const auto setting = [&](const AccuracyPoint* p) {
      return integratorTraits(p->integrator).adaptive ? "rtol " + io::formatNumber(p->rtol, 2)
                                                      : "dt " + accuracyStepLabel(r.duration, p->dt);
    };
    if (order.empty()) {
      fastest.add({io::formatNumber(target), "none reached it", "", "", ""});
      continue;
    }
    fastest.add(
        {io::formatNumber(target), order[0]->integrator, setting(order[0]), io::formatNumber(order[0]->seconds, 3),
         order.size() > 1 ? order[1]->integrator + " (" + io::formatNumber(order[1]->seconds, 3) + " s)" : "-"});
  }
  md << fastest.markdown() << "\n";

  md << "## Every point\n\n";
  io::TextTable all{{"integrator", "dt (s)", "rtol", "steps", "evaluations", "final error (m)", "RMS error (m)",
                     "run time (s)", "in fit"}};
  for (const AccuracyPoint& p : r.points)
    all.add({p.integrator, accuracyStepLabel(r.duration, p.dt), p.rtol > 0 ? io::formatNumber(p.rtol, 2) : "-",
             std::to_string(p.steps), std::to_string(p.evaluations),
             p.diverged ? "diverged" : io::formatNumber(p.final_error, 3),
             p.diverged ? "diverged" : io::formatNumber(p.rms_error, 3),
             p.diverged ? "-" : io::formatNumber(p.seconds, 3), p.in_fit ? "yes" : "no"});
  md << all.markdown() << "\n";

  md << "## Left out (diverged or failed)\n\n";
  bool any = false;
  for (const AccuracyPoint& p : r.points)
    if (p.diverged) {
      md << "- " << p.integrator << " at "
         << (integratorTraits(p.integrator).adaptive ? "rtol " + io::formatNumber(p.rtol, 2)
                                                     : "dt = " + accuracyStepLabel(r.duration, p.dt))
         << ": " << p.failure << "\n";
      any = true;
    }
  if (!any) md << "None.\n";
  return md.str();
}

PlotResult writeAccuracyOutputs(const AccuracyResult& r, const fs::path& out, const std::string& gnuplot) {
  io::TextTable csv{{"scene", "integrator", "dt", "rtol", "mean_step", "steps", "evaluations", "final_error",
                     "rms_error", "seconds", "diverged", "in_fit", "failure", "has_colliders"}};
  for (const AccuracyPoint& p : r.points)
    csv.add({r.scene_name, p.integrator, io::formatNumber(p.dt, 17), io::formatNumber(p.rtol, 3),
             io::formatNumber(p.mean_step, 17), std::to_string(p.steps), std::to_string(p.evaluations),
             io::formatNumber(p.final_error, 17), io::formatNumber(p.rms_error, 17), io::formatNumber(p.seconds, 6),
             p.diverged ? "1" : "0", p.in_fit ? "1" : "0", p.failure, r.has_colliders ? "1" : "0"});

  // Work-precision diagram (SciML style): error on x, run time on y, log-log, one curve per integrator; two panels.
  WorkPrecisionPlot plot;
  plot.comment = "Work-precision diagram of " + r.scene_name + ": gnuplot accuracy.gp (writes accuracy.png)";
  plot.setup = "set ylabel 'run time (s)'\n";
  for (const AccuracyFit& f : r.fits) {
    WorkPrecisionCurve& curve = plot.curves.emplace_back();
    curve.title = f.integrator;
    for (const AccuracyPoint& p : r.points)
      if (p.integrator == f.integrator && !p.diverged && p.final_error > 0 && p.rms_error > 0)
        curve.rows.push_back(io::formatNumber(p.final_error, 10) + " " + io::formatNumber(p.rms_error, 10) + " " +
                             io::formatNumber(p.seconds, 6));
  }
  plot.layout_setup = "set format x '%.0e'\n";
  plot.title =
      "wobble study accuracy: " + r.scene_name + (r.has_colliders ? " (colliders: orders not meaningful)" : "");
  plot.panels[0] = {"set xlabel 'final error (m)'\n", "1:3", ""};
  plot.panels[1] = {"set xlabel 'RMS error over frames (m)'\n", "2:3", ""};
  fs::create_directories(out);
  io::writeTextFile(out / "accuracy.md", accuracyMarkdown(r));
  return writeWorkPrecision(out, "accuracy", csv, plot, gnuplot);
}

}  // namespace wobble
