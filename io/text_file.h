// Whole text files. writeTextFile: written under a temporary name and renamed into place (io/atomic_file.h), so a
// reader never sees half a CSV or Markdown table; path's folder must exist. readTextFile: a file's bytes as they are
// (no newline translation). Both throw std::runtime_error naming the file and the OS's reason
// ("<path>: cannot read: No such file or directory").
#pragma once
#include <filesystem>
#include <string>

namespace wobble::io {

void writeTextFile(const std::filesystem::path& path, const std::string& text);
std::string readTextFile(const std::filesystem::path& path);

}  // namespace wobble::io
