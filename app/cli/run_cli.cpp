// `wobble run` on the command line: options, the report line, and exit statuses.
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "app/cli/max_disk_option.h"
#include "app/cli/max_memory_option.h"
#include "app/cli/render_flags.h"
#include "app/commands/run_command.h"
#include "app/output/interrupt.h"
#include "sim/integrators/integrator.h"

namespace wobble {
namespace {

std::string integratorList() {
  std::string list;
  for (std::string_view n : integratorNames()) list += (list.empty() ? "" : ", ") + std::string(n);
  return list;
}

void printReport(const RunReport& r) {
  std::printf("wrote %d frame(s) %d..%d to %s (%ld steps, %.3f s simulated; simulate %.2f s, export %.2f s)\n",
              r.frames_written, r.first_frame, r.first_frame + std::max(0, r.frames_written - 1), r.out.c_str(),
              r.steps, r.simulated_time, r.seconds_simulate, r.seconds_export);
  if (r.frames_rendered > 0 || r.frames_skipped > 0)
    std::printf("rendered %d frame(s) into %s (%.2f s)%s%s\n", r.frames_rendered, (r.out / "frames").c_str(),
                r.seconds_render, r.video ? "; video " : "", r.video ? r.video->c_str() : "");
  if (r.frames_skipped > 0)
    std::printf("skipped %d frame(s) already rendered with the same settings\n", r.frames_skipped);
  if (const auto& e = r.error_estimate) {
    std::printf(
        "estimated error: max %.3g m, RMS %.3g m, at the last frame %.3g m over %d frame(s) (dt/2 rerun, "
        "Richardson order %d; %.2f s)\n",
        e->max_error, e->rms_error, e->final_max_error, e->frames, e->order, e->seconds);
    if (!e->failure.empty()) std::printf("  (partial: %s)\n", e->failure.c_str());
  }
}

}  // namespace

void addRunCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand(
      "run", "Simulate a scene; write OUT/mesh/<body>_NNNN.obj, OUT/run.json and OUT/frames/<scene>_NNNN.png");
  cmd->add_option("scene", options->scene, "Scene file (TOML)")->capture_default_str();
  cmd->add_option("--integrator", options->integrator, "Integrator: " + integratorList());
  cmd->add_option("--dt", options->dt, "Time step in seconds (overrides simulation.dt)");
  cmd->add_option("--frames", options->frames, "Frames to write, 1-based and inclusive: A:B or A (e.g. 1:60)");
  cmd->add_option("--out", options->out, "Output folder (default out/<scene name>)");
  cmd->add_option("--set", options->sets,
                  "Override a scene key, KEY=VALUE in TOML syntax (repeatable), e.g. --set jelly.ks=2800");
  addRenderFlags(*cmd, options->render);
  addSkipExistingFlag(*cmd, options->skip_existing);
  addMaxMemoryOption(*cmd);
  addMaxDiskOption(*cmd);
  cmd->add_flag("--pc2", options->pc2,
                "Also write OUT/mesh/<body>.pc2, a point cache for Blender (overrides output.pc2; see `wobble blend`)");
  cmd->add_flag("--estimate-error", options->estimate_error,
                "Also run at dt/2 and report the estimated position error at the frames (doubles the run time)");
  cmd->footer("Example:\n  wobble run scenes/cloth_sphere.toml --frames 1:30 --out out/test --set cloth.ks=25000");
  cmd->callback([options, &status] {
    installInterruptHandlers();
    const RunReport report = runScene(*options);
    if (report.files_cleared > 0)
      std::fprintf(stderr, "wobble: removed %d file(s) of an earlier run from %s (meshes, frames, video)\n",
                   report.files_cleared, report.out.c_str());
    printReport(report);
    if (report.blow_up) {
      std::fprintf(stderr, "wobble: %s\n", report.blow_up_message.c_str());
      status = kExitBlowUp;
    }
    if (report.energy_gain) status = kExitBlowUp;  // its message went to stderr when it stopped the run
    if (report.interrupted)
      std::fprintf(stderr, "wobble: interrupted: stopped after frame %d; %s says so\n",
                   report.first_frame + report.frames_written - 1, (report.out / "run.json").c_str());
    status = exitStatusAfterSignals(status);
  });
}

}  // namespace wobble
