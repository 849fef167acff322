// `wobble render` on the command line: re-render a run's OBJ sequence (render_command.h).
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "app/cli/max_disk_option.h"
#include "app/cli/max_memory_option.h"
#include "app/cli/render_flags.h"
#include "app/commands/render_command.h"
#include "app/output/interrupt.h"

namespace wobble {

void addRenderCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<RenderCommandOptions>();
  CLI::App* cmd =
      app.add_subcommand("render",
                         "Render a run's OBJ sequence again without simulating (OUT, or OUT/mesh with --scene): "
                         "OUT/frames/<scene>_NNNN.png");
  cmd->add_option("mesh_dir", options->mesh_dir,
                  "A run's folder OUT (its carried scene), or a folder of <body>_NNNN.obj files (with --scene)")
      ->required();
  cmd->add_option("--scene", options->scene,
                  "The scene the sequence was run from (default: the one the run carried into OUT/scene)");
  cmd->add_option("--frames", options->frames, "Frames to render, 1-based and inclusive: A:B or A (default: all)");
  cmd->add_option("--out", options->out, "Output folder (default: the folder that holds MESH_DIR)");
  cmd->add_option("--set", options->sets, "Override a scene key, KEY=VALUE in TOML syntax (repeatable)");
  addMaxMemoryOption(*cmd);
  addMaxDiskOption(*cmd);
  addRenderFlags(*cmd, options->render);
  addSkipExistingFlag(*cmd, options->skip_existing);
  cmd->footer(
      "Examples:\n  wobble render out/jelly_slope --frames 1:30 --spp 32\n"
      "  wobble render out/jelly_slope/mesh --scene scenes/jelly_slope.toml --frames 1:30\n"
      "Pieces (several at once into one OUT): wobble frames OUT --chunks N, one --frames A:B each, with "
      "--skip-existing; then wobble video OUT.");
  cmd->callback([options, &status] {
    installInterruptHandlers();
    const RenderCommandReport r = renderSequence(*options);
    std::printf("rendered %d frame(s) %d..%d into %s (%.2f s)%s%s\n", r.frames_rendered, r.first_frame, r.last_frame,
                r.out.c_str(), r.seconds, r.video ? "; video " : "", r.video ? r.video->c_str() : "");
    if (r.piece_without_video)
      std::printf("no video for a piece (--frames); when every piece is done: wobble video %s\n", r.out.c_str());
    if (options->skip_existing)
      std::printf("skipped %d frame(s) already rendered with the same settings\n", r.frames_skipped);
    if (interrupted())
      std::fprintf(stderr, "wobble: interrupted: stopped after frame %d\n",
                   r.first_frame + r.frames_rendered + r.frames_skipped - 1);
    status = exitStatusAfterSignals(kExitOk);
  });
}

}  // namespace wobble
