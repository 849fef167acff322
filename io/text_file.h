// writeTextFile: a whole text file written under a temporary name and renamed into place (io/atomic_file.h), so
// a reader never sees half a CSV or Markdown table. Parameters: path (its folder must exist), text.
// Throws std::runtime_error naming the file when it cannot be written.
#pragma once
#include <filesystem>
#include <string>

namespace wobble::io {

void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace wobble::io
