#include "io/text_file.h"

#include "io/atomic_file.h"

namespace wobble::io {

void writeTextFile(const std::filesystem::path& path, const std::string& text) { io::writeFileAtomically(path, text); }

}  // namespace wobble::io
