#include "app/scene/scene_budget.h"

#include "app/scene/scene_file.h"
#include "app/scene/table_reader.h"

namespace wobble {

[[noreturn]] void failOverBudget(TableReader& r, const SceneFile& scene, std::string_view key, const SceneEstimate& e,
                                 const std::string& hint) {
  const bool implicit = integratorTraits(scene.integrator).implicit;
  r.fail(key, "the scene would need " + e.describe(implicit) + ", above the memory budget of " +
                  formatBytes(scene.memory_budget) + " (--max-memory; the default is half of physical memory)" + hint);
}

void reserveBody(TableReader& r, SceneFile& scene, std::string_view key, int value,
                 const std::function<BodySize(int)>& sizeOf) {
  const bool implicit = integratorTraits(scene.integrator).implicit;
  const auto fits = [&](int v) {
    const BodySize b = sizeOf(v);
    SceneEstimate e = scene.estimate;
    e.add(b);
    return b.particles <= kMaxBodyParticles && e.bytes(implicit) <= scene.memory_budget;
  };
  if (fits(value)) {
    scene.estimate.add(sizeOf(value));
    return;
  }
  int lo = 1, hi = value;  // fits(lo) or lo == 1; !fits(hi)
  while (hi - lo > 1) (fits(lo + (hi - lo) / 2) ? lo : hi) = lo + (hi - lo) / 2;
  const std::string hint = lo >= 2 ? "; " + std::string(key) + " <= " + std::to_string(lo) + " would fit" : "";
  const BodySize b = sizeOf(value);
  if (b.particles > kMaxBodyParticles)
    r.fail(key, std::to_string(b.particles) + " particles, above the " + std::to_string(kMaxBodyParticles) +
                    " one body may have (32-bit particle indices)" + hint);
  SceneEstimate e = scene.estimate;
  e.add(b);
  failOverBudget(r, scene, key, e, hint);
}

}  // namespace wobble
