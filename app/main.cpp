// wobble: offline simulator and exporter for mass-spring soft bodies. Subcommands: run.
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "run_command.h"
#include "scene_error.h"
#include "sim/integrators/integrator.h"

namespace {

std::string integratorList() {
  std::string list;
  for (std::string_view n : wobble::integratorNames()) list += (list.empty() ? "" : ", ") + std::string(n);
  return list;
}

void printReport(const wobble::RunReport& r) {
  std::printf("wrote %d frame(s) %d..%d to %s (%ld steps, %.3f s simulated; simulate %.2f s, export %.2f s)\n",
              r.frames_written, r.first_frame, r.first_frame + std::max(0, r.frames_written - 1), r.out.c_str(), r.steps,
              r.simulated_time, r.seconds_simulate, r.seconds_export);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"wobble: simulate mass-spring jellies and cloths from a scene file, export OBJ sequences."};
  app.require_subcommand(1);
  app.footer("Example:\n  wobble run scenes/jelly_slope.toml --integrator midpoint --set jelly.ks=2800\n"
             "Exit status: 0 done, 1 I/O error, 2 bad input (nothing written), 3 the simulation blew up.");

  wobble::RunOptions run;
  CLI::App* run_cmd = app.add_subcommand("run", "Simulate a scene; write OUT/mesh/<body>_NNNN.obj and OUT/run.json");
  run_cmd->add_option("scene", run.scene, "Scene file (TOML)")->capture_default_str();
  run_cmd->add_option("--integrator", run.integrator, "Integrator: " + integratorList());
  run_cmd->add_option("--dt", run.dt, "Time step in seconds (overrides simulation.dt)");
  run_cmd->add_option("--frames", run.frames, "Frames to write, 1-based and inclusive: A:B or A (e.g. 1:60)");
  run_cmd->add_option("--out", run.out, "Output folder (default out/<scene name>)");
  run_cmd->add_option("--set", run.sets, "Override a scene key, KEY=VALUE in TOML syntax (repeatable), e.g. "
                                         "--set jelly.ks=2800 --set simulation.duration=2");
  run_cmd->footer("Example:\n  wobble run scenes/cloth_sphere.toml --frames 1:30 --out out/test --set cloth.ks=25000");

  CLI11_PARSE(app, argc, argv);
  try {
    const wobble::RunReport report = wobble::runScene(run);
    printReport(report);
    if (report.blow_up) {
      std::fprintf(stderr, "wobble: %s\n", report.blow_up_message.c_str());
      return 3;
    }
    return 0;
  } catch (const wobble::SceneError& e) {
    std::fprintf(stderr, "wobble: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wobble: error: %s\n", e.what());
    return 1;
  }
}
