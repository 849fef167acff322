// writeAtomically: produce a file under a temporary name in the target's directory, then rename it into place.
// rename() within one directory (one file system) is atomic on POSIX, so readers see the old file or the complete
// new one, never a partial write. If `write` throws, the temporary file is removed and the exception propagates.
//
// Parameters: target (final path; its directory must exist), write (callback that creates the file at the path it
// is given).
#pragma once
#include <filesystem>
#include <functional>

namespace wobble::render {

void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temp)>& write);

}  // namespace wobble::render
