// `wobble blend OUT`: a run's Blender scene in one step. Reads OUT/run.json (the scene file and the overrides the
// run used, its frames and rate) and the run's point caches (OUT/mesh/<body>.pc2 with their base meshes <body>.obj,
// from `wobble run --pc2` or `[output] pc2 = true`), and has Blender (an external program, like ffmpeg) build
// OUT/<scene>.blend with app/blender/make_blend.py, which the binary carries: each body one object with its
// material and a Mesh Cache modifier on its PC2, the colliders (moving ones keyframed), the camera (a follow camera
// baked as one keyframe per frame), a sun from render.sun_direction, the frame range and rate.
// The .blend is saved under a temporary name and renamed; it refers to the point caches and textures by paths
// relative to OUT.
#pragma once
#include <filesystem>
#include <optional>

namespace wobble {

struct BlendOptions {
  std::filesystem::path out;                   // a run's folder
  std::optional<std::filesystem::path> scene;  // default: run.json's "scene"
};

struct BlendReport {
  std::filesystem::path blend;
  int first_frame = 0, last_frame = 0;
  int bodies = 0, colliders = 0;
  int camera_keys = 0;       // keyframes of a follow camera (0: a fixed camera)
  bool interrupted = false;  // SIGINT/SIGTERM: Blender was ended, no .blend (interrupt.h)
};

// Throws InputError (exit 2) for a folder without a run's run.json or point caches, or that another run holds;
// std::runtime_error when Blender is not on PATH or fails (its output is in the message).
BlendReport makeBlend(const BlendOptions& options);

}  // namespace wobble
