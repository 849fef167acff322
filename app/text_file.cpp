#include "text_file.h"

#include <fstream>
#include <stdexcept>

#include "render/atomic_file.h"

namespace wobble {

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
  render::writeAtomically(path, [&](const std::filesystem::path& temp) {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
  });
}

}  // namespace wobble
