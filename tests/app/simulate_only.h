// The options of a quiet `wobble run` of a shipped scene that simulates only (no pictures, no progress line), as the
// contact and report tests run them.
#pragma once
#include <filesystem>
#include <string>

#include "app/commands/run_scene.h"
#include "tests/app/scratch_dir.h"

namespace wobble::testing {

// scenes/NAME.toml into out; an empty integrator or dt <= 0 keeps the scene's own.
inline RunOptions simulateOnly(const std::string& name, const std::filesystem::path& out,
                               const std::string& integrator = "", double dt = 0) {
  RunOptions o;
  o.scene = sourceDir() / "scenes" / (name + ".toml");
  o.out = out;
  o.render.render = "none";
  o.progress = false;
  if (!integrator.empty()) o.integrator = integrator;
  if (dt > 0) o.dt = dt;
  return o;
}

}  // namespace wobble::testing
