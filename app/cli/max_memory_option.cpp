#include "app/cli/max_memory_option.h"

#include <cstdint>

#include "app/scene/scene_limits.h"

namespace wobble {

void addMaxMemoryOption(CLI::App& cmd) {
  cmd.add_option_function<std::uint64_t>(
         "--max-memory", [](std::uint64_t bytes) { setMemoryBudget(bytes); },
         "Memory budget for the scene (e.g. 8GB, 512MB; KB = 1024 bytes); a scene estimated above it is refused "
         "(default: half of physical memory, " +
             formatBytes(defaultMemoryBudget()) + " here)")
      ->transform(CLI::AsSizeValue(false))
      ->check(CLI::PositiveNumber);
}

}  // namespace wobble
