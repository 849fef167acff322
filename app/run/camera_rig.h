// CameraRig: the render camera of each frame, from the scene's [camera] table.
//   Fixed: position and look_at as given. Missing ones are framed automatically: the view looks at the centre of
//   the bodies and finite colliders at t = 0 (a sphere; an elevator over its whole travel) from the front right and
//   above, far enough back that their bounding sphere fits the vertical field of view.
//   follow = BODY: position and look_at are frame 1's view; later frames move both by how far the body's surface
//   centroid has moved since frame 1, smoothed (double exponential smoothing with time constant follow_smoothing:
//   no lag at constant velocity, and the bounces' sudden turns come out smooth).
// Depth of field: camera.aperture is the thin lens's radius; camera.focus a distance, or the followed body, whose
// smoothed centroid's distance along the view is then the focus of every frame. The camera moves with that same
// smoothed centroid, so this distance is the same at every instant: the frame's time, the shutter's middle and its
// opening alike (a blurred frame's lens does not refocus while the shutter is open, and needs not to).
// The smoothing needs the frames in order (observe()); it is a function of those centroids only, so a run and a
// later `wobble render` of its OBJ sequence move the camera the same way. Frame 1's centroid is the body's initial
// state (from the scene); a sequence that starts later starts the smoothing at its first frame.
#pragma once
#include <span>

#include "app/scene/scene_file.h"
#include "render/camera.h"
#include "sim/surface.h"

namespace wobble {

class CameraRig {
 public:
  explicit CameraRig(const SceneFile& scene);

  // Index of the followed body in scene.system->bodies(), or -1 for a fixed camera.
  int followedBody() const { return followed_; }
  // Feed frame k's followed surface: consecutive frames, from 1 or from the first one there is (no-op when nothing is
  // followed). Throws std::logic_error on a gap.
  void observe(int frame, const SurfaceFrame& followed);
  // The same from the simulation's flat state: the followed body's surface evaluated at x (no-op when fixed).
  void observe(int frame, const MassSpringSystem& system, const VecX& x);
  render::CameraParams params() const;

 private:
  Vec3 position_, look_at_, up_;
  double fov_deg_;
  double aperture_, focus_;
  bool focus_follow_;
  int width_, height_;
  int followed_ = -1;
  double alpha_ = 1;  // smoothing weight per frame
  int last_frame_ = 0;
  Vec3 first_, s1_, s2_;  // centroid at frame 1; first and second smoothed centroids
};

// Mean of a surface's vertex positions, in double.
Vec3 centroid(const SurfaceFrame& surface);

}  // namespace wobble
