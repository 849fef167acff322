#include "io/text_file.h"

#include "io/atomic_file.h"

namespace wobble {

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
  io::writeFileAtomically(path, text);
}

}  // namespace wobble
