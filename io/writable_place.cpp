#include "io/writable_place.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace fs = std::filesystem;

namespace wobble::io {

namespace {

[[noreturn]] void refuse(const fs::path& folder, const fs::path& asked, const std::string& reason) {
  std::string where;
  if (asked != folder) where = " (" + asked.string() + ")";
  throw std::runtime_error(folder.string() + ": cannot write there" + where + ": " + reason);
}

}  // namespace

void checkWritable(const fs::path& folder) {
  // The nearest existing ancestor; "." for a relative path none of whose folders exist.
  fs::path at = folder.empty() ? fs::path(".") : folder;
  std::error_code error;
  while (!fs::exists(at, error)) {
    if (!at.has_parent_path() || at.parent_path() == at) {
      at = at.is_absolute() ? at.root_path() : fs::path(".");
      break;
    }
    at = at.parent_path();
  }
  if (!fs::is_directory(at, error)) refuse(folder, at, std::strerror(ENOTDIR) + std::string(": a file is in the way"));
  const int fd = ::open(at.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
  if (fd >= 0) {
    ::close(fd);
    return;
  }
  const int reason = errno;
  if (reason != EOPNOTSUPP && reason != EISDIR && reason != EINVAL) refuse(folder, at, std::strerror(reason));
  if (::access(at.c_str(), W_OK | X_OK) != 0) refuse(folder, at, std::strerror(errno));
}

}  // namespace wobble::io
