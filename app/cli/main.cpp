// wobble: offline simulator, renderer and exporter for mass-spring soft bodies. One binary, one subcommand per job.
#include <malloc.h>

#include <cstdio>

#include "app/cli/commands.h"
#include "app/scene/input_error.h"

int main(int argc, char** argv) {
  // A frame's buffers (film layers, denoiser planes: tens of MB) are freed and allocated again every frame. glibc
  // serves blocks that large with fresh mmap()s, so every frame would pay for zeroing new pages; keeping
  // them in the heap lets frames reuse the memory.
  mallopt(M_MMAP_THRESHOLD, 512 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  CLI::App app{"wobble: simulate mass-spring jellies and cloths from a scene file, export OBJ sequences, render them."};
  app.require_subcommand(1);
  app.footer(
      "Example:\n  wobble run scenes/jelly_slope.toml --integrator midpoint --set jelly.ks=2800\n"
      "Exit status: 0 done, 1 error, 2 bad input (nothing written) or OUT held by another run, 3 the simulation "
      "blew up, 130/143 interrupted (SIGINT/SIGTERM) after a complete frame.");
  int status = wobble::kExitOk;
  wobble::addRunCommand(app, status);
  wobble::addRenderCommand(app, status);
  wobble::addDiffCommand(app, status);
  wobble::addBlendCommand(app, status);
  wobble::addCompareCommand(app, status);
  wobble::addVideoCommand(app, status);
  wobble::addFramesCommand(app, status);
  wobble::addStudyCommand(app, status);
  std::vector<std::string> args = wobble::idiffSpelling({argv, argv + argc});
  std::vector<char*> spelled;
  for (std::string& a : args) spelled.push_back(a.data());
  try {
    app.parse(int(spelled.size()), spelled.data());
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : wobble::kExitBadInput;
  } catch (const wobble::InputError& e) {
    std::fprintf(stderr, "wobble: %s\n", e.what());
    return wobble::kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wobble: error: %s\n", e.what());
    return wobble::kExitError;
  }
  return status;
}
