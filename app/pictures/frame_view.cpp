#include "app/pictures/frame_view.h"

#include "app/run/run_driver.h"
#include "app/scene/input_error.h"

namespace wobble {

FrameView simulateTo(const SceneFile& scene, int frame) {
  RunDriver run(scene, true);
  while (run.frame() < frame)
    if (const auto blow_up = run.next())
      throw InputError(scene.file.string() + ": the simulation blew up before frame " + std::to_string(frame) + ": " +
                       blow_up->message(scene.dt));
  const PosedFrame posed = run.posed();
  FrameView view{RenderScene(scene), posed.camera, posed.motionBlur()};
  view.scene.update(posed.times, posed.poses);
  return view;
}

}  // namespace wobble
