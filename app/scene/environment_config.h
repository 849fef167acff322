// The environment map a scene names: render.environment (an equirectangular Radiance .hdr or OpenEXR .exr file,
// relative to the scene file), render.environment_rotation (degrees about the up axis) and
// render.environment_strength (a factor on its radiance). render/environment.h is the renderer's side;
// scenes/README.md documents the keys.
#pragma once
#include <filesystem>

namespace wobble {

class TableReader;
struct SceneFile;

struct EnvironmentConfig {
  std::filesystem::path file;  // empty: the gradient sky
  double rotation_deg = 0;
  double strength = 1;
  bool named() const { return !file.empty(); }
};

// Reads the three keys from the [render] table and checks the file from its header alone (it exists, is an image of
// linear radiance, twice as wide as high, at most kMaxEnvironmentSide high, fits the memory budget); the pixels are
// read when the renderer's scene is built.
EnvironmentConfig readEnvironment(TableReader& render, SceneFile& scene);

}  // namespace wobble
