// `wobble blend OUT` on the command line (blend_command.h).
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "app/commands/blend_command.h"
#include "app/output/interrupt.h"

namespace wobble {

void addBlendCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<BlendOptions>();
  CLI::App* cmd = app.add_subcommand(
      "blend",
      "Build OUT/<scene>.blend from a run's point caches with Blender (bodies with a Mesh Cache modifier, "
      "colliders, camera, wobble's materials, sun, sky and tone curve for Cycles)");
  cmd->add_option("out", options->out, "A run's output folder (wobble run --pc2)")->required();
  cmd->add_option("--scene", options->scene, "Scene file (default: the one in OUT/run.json)");
  cmd->add_flag("--pack", options->pack,
                "Pack the images (baked textures, body textures, environment map) into the .blend; the point caches "
                "stay files beside it (a Mesh Cache modifier reads its file)");
  cmd->footer(
      "Example:\n  wobble run scenes/jelly_slope.toml --render none && wobble blend out/jelly_slope && "
      "blender out/jelly_slope/jelly_slope.blend\n"
      "Exit status: 0 done, 1 Blender missing or failed or a file for the .blend not writable, 2 bad input (no run or "
      "no point cache in OUT), "
      "130/143 interrupted.");
  cmd->callback([options, &status] {
    installInterruptHandlers();
    const BlendReport r = makeBlend(*options);
    if (!r.interrupted)
      std::printf("wrote %s: %d bod%s with a Mesh Cache modifier, %d collider(s), frames %d..%d, camera %s\n",
                  r.blend.c_str(), r.bodies, r.bodies == 1 ? "y" : "ies", r.colliders, r.first_frame, r.last_frame,
                  r.camera_keys > 0 ? ("following, " + std::to_string(r.camera_keys) + " keyframes").c_str() : "fixed");
    status = exitStatusAfterSignals(status);
  });
}

}  // namespace wobble
