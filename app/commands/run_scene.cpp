#include "app/commands/run_scene.h"

namespace wobble {
namespace {

SceneFlags sceneFlags(const RunOptions& options) {
  SceneFlags flags;
  if (options.integrator) flags.set("simulation.integrator", "--integrator", *options.integrator);
  if (options.dt) flags.set("simulation.dt", "--dt", *options.dt);
  if (options.pc2) flags.set("output.pc2", "--pc2", true);
  flags.add(renderFlagSettings(options.render));
  return flags;
}

}  // namespace

SceneFile loadRunScene(const RunOptions& options, std::vector<std::string>* overrides) {
  const SceneFlags flags = sceneFlags(options);
  SceneFile scene = loadScene(options.scene, options.sets, flags);
  if (overrides) {
    *overrides = options.sets;
    for (const std::string& o : flags.yieldingTo(options.sets).record()) overrides->push_back(o);
  }
  return scene;
}

}  // namespace wobble
