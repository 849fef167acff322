// self_intersections: runs a scene as `wobble run` does and counts, at every frame, each body's triangles that cross
// its own (issue 53's squeezed well: bench/issue53_check.sh). The oracle is the independent triangle-triangle test of
// tests/sim/triangle_intersection.h (Moller 1997), the self-contact tests' own: two triangles of one body that share
// no particle and touch or cross count as a pair. The run writes OUT as `wobble run --render none` does (run.json,
// meshes unless output.obj = false).
// Usage: build/self_intersections SCENE --out OUT [--integrator NAME] [--dt S] [--set KEY=VALUE ...]
// Prints a line per body: the most intersecting pairs at any frame, and at how many frames there were any; exits with
// the run's status (0; 3 when it blew up or gained energy; 2 for bad input).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/commands/run_command.h"
#include "app/output/interrupt.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "tests/sim/triangle_intersection.h"

int main(int argc, char** argv) {
  using namespace wobble;
  RunOptions o;
  o.render.render = "none";
  o.progress = false;
  std::string out;
  CLI::App app{"Each body's self-intersecting triangle pairs over a run, by an independent test"};
  app.add_option("scene", o.scene, "Scene file (TOML)")->required();
  app.add_option("--out", out, "Output folder of the run")->required();
  app.add_option("--integrator", o.integrator, "Integrator (as wobble run's)");
  app.add_option("--dt", o.dt, "Time step in seconds (as wobble run's)");
  app.add_option("--set", o.sets, "Override a scene key, KEY=VALUE (as wobble run's)");
  CLI11_PARSE(app, argc, argv);
  o.out = out;
  try {
    // Each body's triangles alone: pairs between bodies are not counted.
    const SceneFile scene = loadRunScene(o);
    const auto& bodies = scene.system->bodies();
    std::vector<testing::ParticleTriangles> surfaces(bodies.size());
    for (std::size_t b = 0; b < bodies.size(); ++b)
      testing::addSurface(surfaces[b], bodies[b].body.surface, bodies[b].first, 0);
    std::vector<int> worst(bodies.size(), 0), frames_with(bodies.size(), 0);
    int frames = 0;
    o.on_frame = [&](int, const VecX& x) {
      ++frames;
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        const int pairs = testing::intersectingPairs(surfaces[b], x);
        worst[b] = std::max(worst[b], pairs);
        frames_with[b] += pairs > 0;
      }
    };
    const RunReport r = runScene(o);
    for (std::size_t b = 0; b < bodies.size(); ++b)
      std::printf("%s: at most %d self-intersecting triangle pairs in a frame, %d of %d frames with any\n",
                  bodies[b].body.name.c_str(), worst[b], frames_with[b], frames);
    if (r.blow_up) std::printf("%s\n", r.blow_up_message.c_str());
    if (r.energy_gain) std::printf("%s\n", r.energy_gain_message.c_str());
    return r.blow_up || r.energy_gain ? kExitBlowUp : kExitOk;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return kExitError;
  }
}
