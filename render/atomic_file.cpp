// writeAtomically and the checked byte writer (see atomic_file.h).
#include "atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

namespace wobble::render {
namespace {

// WOBBLE_FAIL_WRITE_AFTER=N: true for the N-th checked write of the process (1-based).
bool injectedFailure() {
  static const long fail_at = [] {
    const char* n = std::getenv("WOBBLE_FAIL_WRITE_AFTER");
    return n ? std::atol(n) : 0L;
  }();
  static std::atomic<long> writes{0};
  return fail_at > 0 && writes.fetch_add(1) + 1 == fail_at;
}

[[noreturn]] void fail(const std::filesystem::path& shown, int error) {
  throw std::runtime_error(shown.string() + ": cannot write: " + std::strerror(error));
}

// Writes bytes to path, checking open, every write (short writes continue) and close.
void writeBytes(const std::filesystem::path& path, std::string_view bytes, const std::filesystem::path& shown) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(shown, errno);
  int error = injectedFailure() ? ENOSPC : 0;
  for (std::size_t done = 0; error == 0 && done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno != EINTR) error = errno;
    if (n > 0) done += std::size_t(n);
  }
  if (::close(fd) != 0 && error == 0) error = errno;  // NFS and friends report write errors at close
  if (error != 0) fail(shown, error);
}

}  // namespace

std::filesystem::path temporarySibling(const std::filesystem::path& target, std::string_view suffix) {
  static std::atomic<unsigned> counter{0};
  std::string name = ".";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "." + std::string
  name += target.filename().string();
  name += ".";
  name += suffix;
  name += std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  return (target.has_parent_path() ? target.parent_path() : std::filesystem::path(".")) / name;
}

void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temp)>& write) {
  namespace fs = std::filesystem;
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir))
    throw std::runtime_error(target.string() + ": directory " + dir.string() + " does not exist");
  const fs::path temp = temporarySibling(target);
  try {
    write(temp);
    fs::rename(temp, target);
  } catch (...) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw;
  }
}

void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes) {
  writeAtomically(target, [&](const std::filesystem::path& temp) { writeBytes(temp, bytes, target); });
}

}  // namespace wobble::render
