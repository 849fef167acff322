#include "app/cli/max_disk_option.h"

#include <cstdint>

#include "app/output/disk_budget.h"

namespace wobble {

void addMaxDiskOption(CLI::App& cmd) {
  cmd.add_option_function<std::uint64_t>(
         "--max-disk", [](std::uint64_t bytes) { setDiskBudget(bytes); },
         "Disk budget (e.g. 20GB, 500MB; KB = 1024 bytes): the command estimates what it will write (meshes, point "
         "caches, pictures at their uncompressed size, video) and, before writing anything, refuses above this or "
         "above the free space of --out's file system (default: the free space alone)")
      ->transform(CLI::AsSizeValue(false))
      ->check(CLI::PositiveNumber);
}

}  // namespace wobble
