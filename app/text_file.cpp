#include "text_file.h"

#include "render/atomic_file.h"

namespace wobble {

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
  render::writeFileAtomically(path, text);
}

}  // namespace wobble
