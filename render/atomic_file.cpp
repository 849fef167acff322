// writeAtomically: temporary sibling file + rename (see atomic_file.h).
#include "atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <system_error>

namespace wobble::render {

void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temp)>& write) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir))
    throw std::runtime_error(target.string() + ": directory " + dir.string() + " does not exist");
  // Hidden, unique per process and call, so parallel writers (frames rendered concurrently) never collide.
  std::string name = ".";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "." + std::string
  name += target.filename().string();
  name += ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  const fs::path temp = dir / name;
  try {
    write(temp);
    fs::rename(temp, target);
  } catch (...) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw;
  }
}

}  // namespace wobble::render
