// checkWritable: can a command write into this folder at all? Asked before anything is estimated or written, so a
// read-only file system, a folder without write permission or a file in the way is refused with the operating
// system's own reason (exit 1), not as a disk that is too small.
//
// The folder may not exist yet: its nearest existing ancestor is asked (the folders a command creates go there). The
// kernel answers: an unnamed file is opened there (O_TMPFILE: nothing appears, nothing stays), which fails as a real
// write would (EROFS, EACCES, ENOSPC for inodes, EDQUOT); where the file system has no O_TMPFILE, access(2) with W_OK.
// A non-folder on the way (OUT itself, or one of its parents, is a file) is ENOTDIR, naming that file.
#pragma once
#include <filesystem>

namespace wobble::io {

// Throws std::runtime_error "<folder>: cannot write there: <reason>" (naming the ancestor asked, or the file in the
// way, when it is not the folder itself).
void checkWritable(const std::filesystem::path& folder);

}  // namespace wobble::io
