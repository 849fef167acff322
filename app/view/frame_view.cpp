#include "app/view/frame_view.h"

#include <vector>

#include "app/scene/input_error.h"
#include "app/view/camera_rig.h"
#include "sim/simulation.h"

namespace wobble {

FrameView simulateTo(const SceneFile& scene, int frame) {
  MassSpringSystem& system = *scene.system;
  Simulation sim(system, makeIntegrator(scene.integrator, scene.integrator_options), scene.dt);
  CameraRig rig(scene);
  for (int k = 1; k <= frame; ++k) {
    if (const auto blow_up = sim.advanceTo(scene.frameTime(k)))
      throw InputError(scene.file.string() + ": the simulation blew up before frame " + std::to_string(frame) + ": " +
                       blow_up->message(scene.dt));
    rig.observe(k, system, sim.x());
  }
  std::vector<SurfaceFrame> surfaces;
  for (const BodySlot& slot : system.bodies())
    surfaces.push_back(evaluateSurface(slot.body.surface, sim.x(), slot.first));
  FrameView view{RenderScene(scene), rig.params()};
  view.scene.update(scene.frameTime(frame), surfaces);
  return view;
}

}  // namespace wobble
