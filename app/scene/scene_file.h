// A scene file (TOML, see scenes/README.md) read into what a run needs: simulation settings, the mass-spring system
// with only the bodies and colliders the file names, and per-body textures. --set overrides, then the flags' typed
// settings (scene_flags.h), are laid over the TOML before anything is read, so they get the same checks as the file.
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/scene/render_config.h"
#include "app/scene/scene_file_use.h"
#include "app/scene/scene_flags.h"
#include "app/scene/scene_limits.h"
#include "sim/integrators/integrator.h"
#include "sim/system.h"

namespace wobble {

struct SceneFile {
  std::filesystem::path file;
  std::string name;  // file name without extension: names outputs

  std::string integrator = "rk4";
  IntegratorOptions integrator_options;
  double dt = 0.001;
  double duration = 10;  // simulated seconds
  double fps = 30;       // frames per simulated second
  bool write_obj = true;
  bool write_pc2 = false;  // OUT/mesh/<body>.pc2 and its base mesh <body>.obj (pc2_writer.h)

  std::unique_ptr<MassSpringSystem> system;
  std::map<std::string, std::filesystem::path> textures;  // body name -> texture file, only for bodies naming one
  std::vector<SceneFileUse> files;  // every file the scene reads besides itself (textures, models, environment map)
  std::string text;  // the file after --set and flags, as TOML (keys sorted): what a cache of results may be keyed by
  // The same without the keys that choose which files are written, not what a frame shows (render.png, .exr, .video,
  // output.*, simulation.duration), and with each file key's value (`files`) replaced by the file's content hash: what
  // a frame's picture key hashes (app/output/picture_key.h), the same wherever the files are.
  std::string picture_text;
  RenderConfig render;              // camera, render settings and the look of bodies and colliders (render_config.h)
  std::uint64_t memory_budget = 0;  // bytes the scene's estimate may reach (scene_limits.h)
  SceneEstimate estimate;           // summed as bodies and textures are read, before each is built or loaded
  int body_count = 0;               // the [bodies] entries (known before the first is read)

  // Frame k (1-based) shows simulated time (k - 1) / fps; duration * fps frames, at least one.
  int frameCount() const;
  double frameTime(int frame) const { return (frame - 1) / fps; }
};

// max_memory: the memory budget in bytes, 0 for memoryBudget(); a scene over it, or over any other limit of
// scene_limits.h, is refused before its bodies are built.
// overrides: --set's "dotted.key=value" (value in TOML syntax; a bare word is taken as a string). A first component
// that names a body or collider may omit "bodies." / "colliders.": "jelly.ks=2800".
// flags: the command-line flags' settings, laid over the keys after the overrides. Throws InputError.
SceneFile loadScene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {},
                    const SceneFlags& flags = {}, std::uint64_t max_memory = 0);

}  // namespace wobble
