// Reader of the environment keys of [render] (environment_config.h).
#include "app/scene/environment_config.h"

#include <string>

#include "app/scene/scene_budget.h"
#include "app/scene/scene_file.h"
#include "app/scene/scene_limits.h"
#include "app/scene/table_reader.h"
#include "image/image_header.h"

namespace fs = std::filesystem;

namespace wobble {

EnvironmentConfig readEnvironment(TableReader& r, SceneFile& scene) {
  EnvironmentConfig env;
  const auto name = r.optionalString("environment");
  env.rotation_deg = r.number("environment_rotation", env.rotation_deg);
  env.strength = r.number("environment_strength", env.strength, Range::nonNegative());
  if (!name) {
    for (const char* key : {"environment_rotation", "environment_strength"})
      if (r.node(key)) r.fail(key, "applies to an environment map: set render.environment = \"FILE.hdr\" too");
    return env;
  }
  const fs::path path = r.filePath("environment", *name);
  const std::string allowed =
      "; allowed: an equirectangular Radiance .hdr or OpenEXR .exr file (linear radiance, "
      "twice as wide as high, at most " +
      std::to_string(2 * kMaxEnvironmentSide) + " x " + std::to_string(kMaxEnvironmentSide) +
      " pixels), relative to the scene file";
  if (!fs::is_regular_file(path)) r.fail("environment", "file not found: " + path.string() + allowed);
  std::string reason;
  const auto header = image::readImageHeader(path, reason);
  if (!header) r.fail("environment", path.string() + " is not an image wobble reads (" + reason + ")" + allowed);
  const std::string size = std::to_string(header->width) + " x " + std::to_string(header->height) + " pixels";
  if (!header->linear)
    r.fail("environment",
           path.string() + " is a " + header->format + " image of display values, not radiance" + allowed);
  if (header->width != 2 * header->height)
    r.fail("environment", path.string() + " is " + size + ", not twice as wide as high" + allowed);
  if (header->height > kMaxEnvironmentSide) r.fail("environment", path.string() + " is " + size + allowed);
  SceneEstimate e = scene.estimate;
  e.environment_pixels = std::int64_t(header->width) * header->height;
  if (e.bytes(integratorTraits(scene.integrator).implicit) > scene.memory_budget)
    failOverBudget(r, scene, "environment", e, "");
  scene.estimate = e;
  env.file = path;
  return env;
}

}  // namespace wobble
