// `wobble video OUT` on the command line (video_command.h).
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "app/commands/video_command.h"
#include "app/output/interrupt.h"

namespace wobble {

void addVideoCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<VideoOptions>();
  CLI::App* cmd = app.add_subcommand(
      "video",
      "Encode OUT/frames/<scene>_NNNN.png into OUT/<scene>.mp4 (frames rendered in pieces), checking that "
      "every frame is there");
  cmd->add_option("out", options->out, "Output folder of a run (OUT/run.json names the scene, frames and rate)")
      ->required();
  cmd->add_option("--scene", options->scene, "Scene file giving the name, rate and frames instead of OUT/run.json");
  cmd->add_option("--set", options->sets, "Override a key of --scene, KEY=VALUE (repeatable), as given to render");
  cmd->add_option("--frames", options->frames, "Frames to encode, A:B (default: those the run wrote, or all)");
  cmd->add_flag("--allow-mixed", options->allow_mixed,
                "Encode frames rendered with different settings too (refused by default: a piece rendered with "
                "other flags)");
  cmd->footer(
      "Example:\n  wobble frames out/jelly_slope --chunks 4 | parallel wobble render out/jelly_slope/mesh "
      "--scene scenes/jelly_slope.toml --frames {} --skip-existing\n  wobble video out/jelly_slope\n"
      "Exit status: 0 done, 1 ffmpeg missing or failed, 2 bad input (missing frames, listed; frames of "
      "different sizes or settings), 130/143 interrupted.");
  cmd->callback([options, &status] {
    installInterruptHandlers();
    const VideoReport r = encodeFrames(*options);
    if (r.mp4)
      std::printf("wrote %s: %d frame(s) %d..%d at %g fps (%.2f s)\n", r.mp4->c_str(), r.last_frame - r.first_frame + 1,
                  r.first_frame, r.last_frame, r.fps, r.seconds);
    status = exitStatusAfterSignals(kExitOk);
  });
}

}  // namespace wobble
