// SceneFileUse: a file a scene reads besides itself (a texture, a model, an environment map), recorded as the scene
// is read (TableReader::filePath) so that a run can carry it (app/output/carried_scene.h) and a picture's key can
// hash its bytes rather than its path.
#pragma once
#include <filesystem>
#include <string>

namespace wobble {

struct SceneFileUse {
  std::string key;             // dotted, e.g. "bodies.jelly.texture"
  std::filesystem::path path;  // as resolved: relative to the scene file's folder
};

}  // namespace wobble
