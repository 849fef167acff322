// `wobble blend OUT`: a run's Blender scene in one step, which Cycles renders as wobble's renderer does. Reads
// OUT/run.json (the scene file and the overrides the run used, its frames and rate) and the run's point caches
// (OUT/mesh/<body>.pc2 with their base meshes <body>.obj, from `wobble run --pc2` or `[output] pc2 = true`), and has
// Blender (an external program, like ffmpeg) build OUT/<scene>.blend with app/blender/make_blend.py, which the binary
// carries: each body one object with a Mesh Cache modifier on its PC2, the colliders as wobble draws them (the
// renderer's own triangles and UVs; moving ones keyframed), the camera (a follow camera baked as one keyframe per
// frame), wobble's materials, sun and sky (or environment map), bounces and tone curve (app/blender/cycles_nodes.py),
// the frame range and rate. Procedural textures are baked into OUT/blender/<material>.png and an environment map is
// copied to OUT/blender/; the .blend refers to them, the point caches and the body textures by paths relative to
// OUT (with pack, it holds the images itself). The .blend is saved under a temporary name and renamed; a file that
// cannot be written is an I/O error (std::runtime_error, exit 1) and leaves no .blend.
#pragma once
#include <filesystem>
#include <optional>

namespace wobble {

struct BlendOptions {
  std::filesystem::path out;                   // a run's folder
  std::optional<std::filesystem::path> scene;  // default: run.json's "scene"
  bool pack = false;                           // pack the images (textures, environment map) into the .blend
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
