#include "atomic_file.h"

#include <fstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace wobble {
namespace {

fs::path temporaryFor(const fs::path& path) { return path.parent_path() / ("." + path.filename().string() + ".tmp"); }

}  // namespace

void writeFileAtomically(const fs::path& path, std::string_view text) {
  const fs::path tmp = temporaryFor(path);
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
  }
  fs::rename(tmp, path);
}

void copyFileAtomically(const fs::path& from, const fs::path& to) {
  const fs::path tmp = temporaryFor(to);
  std::error_code error;
  fs::copy_file(from, tmp, fs::copy_options::overwrite_existing, error);
  if (error) throw std::runtime_error("cannot copy " + from.string() + " to " + to.string() + ": " + error.message());
  fs::rename(tmp, to);
}

}  // namespace wobble
