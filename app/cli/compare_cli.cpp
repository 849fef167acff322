// `wobble compare` on the command line: the run flags, --vary, the report lines, and exit statuses.
#include <cstdio>
#include <memory>

#include "app/cli/commands.h"
#include "app/cli/max_memory_option.h"
#include "app/cli/render_flags.h"
#include "app/commands/compare_command.h"
#include "app/compare/tile_label.h"
#include "app/output/interrupt.h"
#include "app/scene/input_error.h"

namespace wobble {

void addCompareCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<CompareOptions>();
  RunOptions& run = options->run;
  CLI::App* cmd =
      app.add_subcommand("compare",
                         "Run a scene under several settings and put them side by side: OUT/<variant>/ (each a run), "
                         "OUT/compare.mp4 with labelled tiles, OUT/compare.md");
  cmd->add_option("scene", run.scene, "Scene file (TOML)")->capture_default_str();
  cmd->add_option("--vary", options->vary,
                  "KEY=V1,V2,...: one variant per value; KEY is integrator, dt or a scene key (jelly.ks). Twice: "
                  "a grid, the first --vary down the rows, the second across the columns")
      ->required();
  cmd->add_option("--integrator", run.integrator, "Integrator of every variant (overrides simulation.integrator)");
  cmd->add_option("--dt", run.dt, "Time step of every variant in seconds (overrides simulation.dt)");
  cmd->add_option("--frames", run.frames, "Frames to write and compare, 1-based and inclusive: A:B or A");
  cmd->add_option("--out", options->out, "Output folder (default out/compare-<scene name>)");
  cmd->add_option("--set", run.sets, "Override a scene key for every variant, KEY=VALUE (repeatable)");
  addRenderFlags(*cmd, run.render);
  addMaxMemoryOption(*cmd);
  cmd->add_flag("--pc2", run.pc2, "Each variant also writes its PC2 point cache (overrides output.pc2)");
  cmd->add_flag("--estimate-error", run.estimate_error,
                "Each variant also runs at dt/2 and compare.md gives its estimated error (doubles the run time)");
  cmd->add_option("--jobs", options->jobs, "Variants run at once (default 0: one per hardware thread)");
  auto piece = std::make_shared<std::string>();
  cmd->add_option("--piece", *piece,
                  "I/N: run only piece I of N of the variants (a farm's task; resumes what it finished); the pictures "
                  "and compare.md come with --gather");
  cmd->add_flag("--gather", options->gather,
                "Run no variant: render the grid, video and compare.md from every --piece's variants in OUT");
  cmd->add_option("--strain-bound", options->strain_bound,
                  "A variant whose largest spring strain passes this has lost its shape (the stability study's)")
      ->capture_default_str();
  cmd->footer(
      "The picture is the size of the scene's frames (camera.resolution, --resolution, --quality); the tiles\n"
      "share it. Example:\n  wobble compare --vary integrator=explicit-euler,pc-euler,midpoint,rk4 "
      "--set jelly.ks=5e4 --dt 1.2e-3");
  cmd->callback([options, piece, &status] {
    installInterruptHandlers();
    if (!piece->empty()) options->piece = parsePiece(*piece);
    if (options->piece && options->gather)
      throw InputError("--piece and --gather: one or the other (a piece, or the pictures and report)");
    const CompareReport r = runCompare(*options);
    for (const CompareVariant& v : r.variants) {
      const RunReport& result = v.report;
      std::printf("%s: %s: %ld steps, %.3f s simulated in %.2f s", (r.out / v.folder).c_str(), v.label.c_str(),
                  result.steps, result.simulated_time, v.wall_seconds);
      if (result.blow_up)
        std::printf("; blew up at t = %s s (step %ld)", labelSeconds(result.blow_up->time).c_str(),
                    result.blow_up->step);
      else if (v.lost_shape_frame)
        std::printf("; lost its shape (strain %s)", shortNumber(v.lost_shape_strain).c_str());
      std::printf("\n");
    }
    if (options->piece) {
      std::printf(
          "piece %s: variants %zu to %zu of %zu (%zu kept from an earlier run) in %s; when every piece is "
          "done: the same command with --gather\n",
          piece->c_str(), r.piece_first + 1, r.piece_last, r.variant_count, r.variants_resumed, r.out.c_str());
      status = exitStatusAfterSignals(kExitOk);
      return;
    }
    if (!options->gather)
      std::printf("ran %zu variant(s), %d at a time, in %.2f s\n", r.variants.size(), r.jobs, r.seconds_runs);
    if (r.grid)
      std::printf("rendered %d frame(s) of %d x %d (%d x %d tiles of %d x %d) into %s (%.2f s)%s%s\n",
                  r.frames_rendered, r.grid->width(), r.grid->height(), r.grid->rows, r.grid->cols, r.grid->tile_width,
                  r.grid->tile_height, (r.out / "frames").c_str(), r.seconds_render, r.video ? "; video " : "",
                  r.video ? r.video->c_str() : "");
    if (r.interrupted)
      std::fprintf(stderr, "wobble: interrupted: no compare.md; each variant's run.json says how far it got\n");
    else std::printf("wrote %s\n", (r.out / "compare.md").c_str());
    status = exitStatusAfterSignals(kExitOk);
  });
}

}  // namespace wobble
