// SequencePoser: the frames of a run read back from its OBJ sequence (`wobble render`), posed as the run posed them:
// the camera rig sees every frame in order (from the first there is, camera_rig.h), and a motion-blurred frame's
// poses are blended linearly from the frame before (blendSurfaces, shutter.h) when that frame was given with every
// body's surface; without it, the frame is still.
#pragma once
#include <span>
#include <vector>

#include "app/run/camera_rig.h"
#include "app/run/posed_frame.h"
#include "app/scene/scene_file.h"

namespace wobble {

class SequencePoser {
 public:
  explicit SequencePoser(const SceneFile& scene);

  // Index of the body the camera follows in scene.system->bodies(), or -1 for a fixed camera.
  int followedBody() const { return rig_.followedBody(); }
  // Frame k's surfaces, every body's in scene body order (a frame only the camera sees may leave all but the
  // followed body's empty); frames in order.
  void observe(int frame, std::span<const SurfaceFrame> surfaces);
  // The frame last observed, posed (it must have every body's surface).
  PosedFrame posed() const;

 private:
  const SceneFile& scene_;
  CameraRig rig_;
  render::CameraParams camera_before_;
  std::vector<SurfaceFrame> current_, previous_;
  int frame_ = 0;
  int previous_frame_ = -1;  // the frame previous_ holds, when it holds every body's surface; else -1
};

}  // namespace wobble
