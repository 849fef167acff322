// writeAtomically and the checked byte writer (see atomic_file.h).
#include "io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
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

// WOBBLE_FAIL_WRITE_AFTER=N[:short|:close] (atomic_file.h): where the N-th checked write (or close) fails.
enum class Fault { None, Before, Short, Close };

struct Injection {
  long at = 0;  // 1-based; 0: none
  Fault fault = Fault::Before;
};

const Injection& injection() {
  static const Injection i = [] {
    Injection r;
    const char* text = std::getenv("WOBBLE_FAIL_WRITE_AFTER");
    if (!text) return r;
    char* rest = nullptr;
    r.at = std::strtol(text, &rest, 10);
    const std::string how = rest;
    r.fault = how == ":short" ? Fault::Short : how == ":close" ? Fault::Close : Fault::Before;
    return r;
  }();
  return i;
}

// The fault this checked write (or, for closing, close) gets: None but for the N-th of its kind.
Fault injectedFault(bool closing) {
  static std::atomic<long> writes{0}, closes{0};
  const Injection& i = injection();
  if (i.at <= 0 || (i.fault == Fault::Close) != closing) return Fault::None;
  return (closing ? closes : writes).fetch_add(1) + 1 == i.at ? i.fault : Fault::None;
}

// close(), checked; 0 or errno.
int closeChecked(int fd) {
  const bool fails = injectedFault(true) == Fault::Close;
  if (::close(fd) != 0) return errno;
  return fails ? ENOSPC : 0;
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
  const Fault fault = injectedFault(false);
  if (fault == Fault::Before) return ENOSPC;
  for (std::size_t done = 0; done < bytes.size();) {
    std::size_t size = bytes.size() - done;
    if (fault == Fault::Short) {
      if (done > 0) return ENOSPC;  // the disk filled during the first write(): the next one fails
      size = std::max<std::size_t>(1, size / 2);
    }
    const ssize_t n = offset < 0 ? ::write(fd, bytes.data() + done, size)
                                 : ::pwrite(fd, bytes.data() + done, size, offset + off_t(done));
    if (n < 0 && errno != EINTR) return errno;
    if (n > 0) done += std::size_t(n);
  }
  return fault == Fault::Short ? ENOSPC : 0;  // a single byte, written whole: the disk is full now all the same
}

// Writes bytes to path, checking open, every write (short writes continue) and close.
void writeBytes(const std::filesystem::path& path, std::string_view bytes, const std::filesystem::path& shown) {
  const int fd = openForWriting(path, shown);
  int error = writeAll(fd, bytes);
  if (const int closed = closeChecked(fd); closed != 0 && error == 0) error = closed;  // NFS reports errors here
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
  const int error = closeChecked(fd);
  std::error_code renamed;
  if (error == 0) std::filesystem::rename(temp_, target_, renamed);
  if (error == 0 && !renamed) return;
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
  if (error != 0) fail(target_, error);
  throw std::runtime_error(target_.string() + ": cannot write: " + renamed.message());
}

}  // namespace wobble::io
