// writeAtomically and the checked byte writer (see atomic_file.h).
#include "io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

namespace wobble::io {
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

int openForWriting(const std::filesystem::path& path, const std::filesystem::path& shown) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(shown, errno);
  return fd;
}

// Writes all of bytes at offset (or at the file position when offset < 0), continuing short writes; 0 or errno.
int writeAll(int fd, std::string_view bytes, off_t offset = -1) {
  if (injectedFailure()) return ENOSPC;
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = offset < 0 ? ::write(fd, bytes.data() + done, bytes.size() - done)
                                 : ::pwrite(fd, bytes.data() + done, bytes.size() - done, offset + off_t(done));
    if (n < 0 && errno != EINTR) return errno;
    if (n > 0) done += std::size_t(n);
  }
  return 0;
}

// Writes bytes to path, checking open, every write (short writes continue) and close.
void writeBytes(const std::filesystem::path& path, std::string_view bytes, const std::filesystem::path& shown) {
  const int fd = openForWriting(path, shown);
  int error = writeAll(fd, bytes);
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

AtomicFileWriter::AtomicFileWriter(std::filesystem::path target)
    : target_(std::move(target)), temp_(temporarySibling(target_)) {
  fd_ = openForWriting(temp_, target_);
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ < 0) return;
  ::close(fd_);
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
}

void AtomicFileWriter::append(std::string_view bytes) {
  if (const int error = writeAll(fd_, bytes); error != 0) fail(target_, error);
}

void AtomicFileWriter::overwrite(std::size_t offset, std::string_view bytes) {
  if (const int error = writeAll(fd_, bytes, off_t(offset)); error != 0) fail(target_, error);
}

void AtomicFileWriter::commit() {
  const int fd = std::exchange(fd_, -1);
  const int error = ::close(fd) != 0 ? errno : 0;
  std::error_code renamed;
  if (error == 0) std::filesystem::rename(temp_, target_, renamed);
  if (error == 0 && !renamed) return;
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
  if (error != 0) fail(target_, error);
  throw std::runtime_error(target_.string() + ": cannot write: " + renamed.message());
}

}  // namespace wobble::io
