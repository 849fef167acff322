// Output files appear whole or not at all: written under a temporary name in the same folder, then renamed.
#pragma once
#include <filesystem>
#include <string_view>

namespace wobble {

// Writes text to path through path + ".tmp" and a rename. Throws std::runtime_error naming the file on failure.
void writeFileAtomically(const std::filesystem::path& path, std::string_view text);
void copyFileAtomically(const std::filesystem::path& from, const std::filesystem::path& to);

}  // namespace wobble
