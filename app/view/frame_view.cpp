#include "app/view/frame_view.h"

#include <vector>

#include "app/scene/input_error.h"
#include "app/view/camera_rig.h"
#include "app/view/shutter.h"
#include "sim/simulation.h"

namespace wobble {

FrameView simulateTo(const SceneFile& scene, int frame) {
  MassSpringSystem& system = *scene.system;
  Simulation sim(system, makeIntegrator(scene.integrator, scene.integrator_options), scene.dt);
  CameraRig rig(scene);
  ShutterRecorder shutter(scene, sim.x());
  sim.observeSteps([&shutter](double t, const VecX& x) { shutter.step(t, x); });
  render::CameraParams before = rig.params();
  for (int k = 1; k <= frame; ++k) {
    shutter.begin(k);
    if (const auto blow_up = sim.advanceTo(scene.frameTime(k)))
      throw InputError(scene.file.string() + ": the simulation blew up before frame " + std::to_string(frame) + ": " +
                       blow_up->message(scene.dt));
    if (k == frame) before = rig.params();
    rig.observe(k, system, sim.x());
  }
  const std::vector<double> times = shutterTimes(scene, frame);
  FrameView view{RenderScene(scene), rig.params(), times.size() > 1};
  if (view.motion_blur) view.camera.shutter_motion = shutterMotion(scene, before.position, view.camera.position);
  view.scene.update(times, surfacesOf(scene, shutter.states(sim.x())));
  return view;
}

}  // namespace wobble
