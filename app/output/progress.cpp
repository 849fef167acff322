#include "app/output/progress.h"

#include <unistd.h>
#include <cstdio>

namespace wobble {

Progress::Progress(std::string what, int total, std::string unit)
    : what_(std::move(what)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {}

void Progress::update(int done, const std::string& note) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && now - last_ < std::chrono::milliseconds(100)) return;  // do not flood the terminal
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double remaining = done > 0 ? elapsed * (total_ - done) / done : 0;
  std::fprintf(stderr, "\r%s: %s %d of %d, elapsed %.1f s, remaining %.1f s%s%s   ", what_.c_str(), unit_.c_str(), done,
               total_, elapsed, remaining, note.empty() ? "" : ", ", note.c_str());
  std::fflush(stderr);
}

void Progress::finish() {
  if (enabled_) std::fputc('\n', stderr);
  enabled_ = false;
}

}  // namespace wobble
