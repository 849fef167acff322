// `wobble frames SCENE_OR_OUT --chunks N` on the command line (frames_command.h): one "A:B" a line on stdout.
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "app/commands/frames_command.h"

namespace wobble {

void addFramesCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<FramesOptions>();
  CLI::App* cmd = app.add_subcommand(
      "frames", "Print the frame ranges of N pieces of a render, one A:B a line (for GNU parallel or a Slurm array)");
  cmd->add_option("source", options->source,
                  "A run's output folder (the frames it wrote, from OUT/run.json) or a scene file (all its frames)")
      ->required();
  cmd->add_option("--chunks", options->chunks, "Number of pieces (contiguous, as even as can be)")->required();
  cmd->add_option("--chunk", options->chunk, "Print only piece I, 1-based (e.g. $SLURM_ARRAY_TASK_ID)");
  cmd->add_option("--frames", options->frames, "Split only frames A:B");
  cmd->add_option("--set", options->sets, "Override a key of the scene file, KEY=VALUE (repeatable)");
  cmd->footer(
      "Example:\n  wobble frames out/jelly_slope --chunks 4 | parallel wobble render out/jelly_slope/mesh "
      "--scene scenes/jelly_slope.toml --frames {} --skip-existing\n"
      "  wobble render ... --frames \"$(wobble frames OUT --chunks 8 --chunk $SLURM_ARRAY_TASK_ID)\"");
  cmd->callback([options, &status] {
    for (const auto& [a, b] : framePieces(*options)) std::printf("%d:%d\n", a, b);
    status = kExitOk;
  });
}

}  // namespace wobble
