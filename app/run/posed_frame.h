// PosedFrame: what a frame's picture shows: every body's surfaces at each instant the frame's shutter is open (one
// instant, the frame's own time, for a still frame; shutter.h), and the camera there, its move over the shutter set
// (render::CameraParams::shutter_motion). RunDriver poses a simulated frame, SequencePoser one read from an OBJ
// sequence; FrameOutput renders either.
#pragma once
#include <vector>

#include "render/camera.h"
#include "sim/surface.h"

namespace wobble {

struct PosedFrame {
  int frame = 0;
  std::vector<double> times;                     // open to close; the last is the frame's own time
  std::vector<std::vector<SurfaceFrame>> poses;  // poses[j][body]: at times[j], in scene body order
  render::CameraParams camera;
  bool motionBlur() const { return times.size() > 1; }
};

}  // namespace wobble
