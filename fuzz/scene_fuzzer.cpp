// Feeds arbitrary bytes to loadScene as a scene file: every input must load or end in an InputError (exit 2); any
// other exception, a crash, a leak or a sanitizer report is a finding. Seed corpus: scenes/*.toml.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"

namespace fs = std::filesystem;

namespace {

// A folder of this process with the shipped textures beside the scene, so that texture keys are read for real.
const fs::path& sceneFile() {
  static const fs::path file = [] {
    const fs::path dir = fs::temp_directory_path() / ("wobble_fuzz_" + std::to_string(getpid()));
    fs::create_directories(dir);
    fs::copy(fs::path(WOBBLE_SOURCE_DIR) / "scenes/textures", dir / "textures",
             fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    return dir / "scene.toml";
  }();
  return file;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Bodies of up to a few MB: large enough for every path of the reader, small enough to keep runs fast.
  wobble::setMemoryBudget(std::uint64_t{64} << 20);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::ofstream(sceneFile(), std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), size);
  try {
    wobble::loadScene(sceneFile());
  } catch (const wobble::InputError&) {
  }
  return 0;
}
