// writeAtomically: produce a file under a temporary name in the target's directory, then rename it into place.
// rename() within one directory (one file system) is atomic on POSIX, so readers see the old file or the complete
// new one, never a partial write. If `write` throws, the temporary file is removed and the exception propagates.
//
// writeFileAtomically is the one checked write every wobble writer ends in: bytes prepared in memory, written with
// every write() and close() checked, so a full disk fails the run naming the file and the OS reason
// ("No space left on device") and never leaves a truncated file under its final name.
//
// Test hook: WOBBLE_FAIL_WRITE_AFTER=N in the environment (read once) makes the N-th checked write of the process
// fail with ENOSPC, as a full disk would: before any byte is written; with N:short, after write() has stored part of
// the bytes (a short write, then ENOSPC for the rest, as a disk that fills during the write); with N:close, at the
// N-th checked close() (every byte written: network file systems report write errors there).
#pragma once
#include <filesystem>
#include <functional>
#include <string_view>

namespace wobble::io {

// Parameters: target (final path; its directory must exist), write (callback that creates the file at the path it
// is given).
void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temp)>& write);

// bytes -> target, through a temporary file. Throws std::runtime_error "<target>: cannot write: <reason>".
void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);

// A file written in pieces (a point cache growing frame by frame) under a temporary name, with the same checks and
// test hook as writeFileAtomically; commit() renames it into place. Destroyed without commit(), it removes the
// temporary file: an exception leaves nothing behind. Throws std::runtime_error "<target>: cannot write: <reason>".
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::filesystem::path target);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void append(std::string_view bytes);
  void overwrite(std::size_t offset, std::string_view bytes);  // bytes already written, e.g. a header's count
  void commit();
  const std::filesystem::path& target() const { return target_; }

 private:
  std::filesystem::path target_, temp_;
  int fd_ = -1;
};

// A hidden sibling name for target, unique per process and call: ".<name>.<suffix><pid>-<counter>", so parallel
// writers and concurrent processes never share a temporary file.
std::filesystem::path temporarySibling(const std::filesystem::path& target, std::string_view suffix = "tmp");

}  // namespace wobble::io
